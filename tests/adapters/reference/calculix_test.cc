#include "adapters/reference/calculix.h"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters::reference {
namespace {

// A box under uniaxial compression along z, its faces x = 0, y = 0 and
// z = 0 held only normal to themselves (symmetry), so that it deforms
// homogeneously: z stretched by `stretch`, free to widen.
Job compressed(const std::string& element, std::array<int, 3> n, double edge, double stretch, Material m) {
  Job job = box(Eigen::Vector3d::Constant(edge), n, element);
  job.material = m;
  job.fixes = {{"XMIN", 1, 0}, {"YMIN", 2, 0}, {"ZMIN", 3, 0}, {"ZMAX", 3, (stretch - 1) * edge}};
  job.reactions = {"ZMAX"};
  return job;
}

// CalculiX's compressible neo-Hookean law, W = C10 (I1bar - 3) + (J - 1)^2
// / D1, in uniaxial stress: the Cauchy stress
//   sigma = 2 C10 / J dev(J^(-2/3) b) + 2 / D1 (J - 1) I,
// with b = diag(t^2, t^2, s^2), its lateral components zero. Returns the
// lateral stretch t and the axial Cauchy stress.
std::pair<double, double> neo_hookean_uniaxial(double young, double poisson, double s) {
  const double c10 = young / (4 * (1 + poisson)), d1 = 6 * (1 - 2 * poisson) / young;
  const auto stress = [&](double t, int axis) {
    const double j = s * t * t, scale = std::pow(j, -2.0 / 3), mean = scale * (2 * t * t + s * s) / 3;
    const double b = scale * (axis == 2 ? s * s : t * t);
    return 2 * c10 / j * (b - mean) + 2 / d1 * (j - 1);
  };
  double lo = 0.5, hi = 2;  // the lateral stress rises with t
  for (int i = 0; i < 200; ++i) (stress(0.5 * (lo + hi), 0) > 0 ? hi : lo) = 0.5 * (lo + hi);
  const double t = 0.5 * (lo + hi);
  return {t, stress(t, 2)};
}

TEST(CalculiX, ABoxIsMeshedWithItsFacesAsSets) {
  const Job q = box({0.01, 0.02, 0.03}, {1, 2, 3});
  EXPECT_EQ(q.elements.size(), 6u);
  EXPECT_EQ(q.nodes.size(), 3u * 5 * 7 - (1 * 2 * 3) - (1 * 2 * 4 + 1 * 3 * 3 + 2 * 3 * 2));  // less centres
  for (const auto& e : q.elements) EXPECT_EQ(e.size(), 20u);
  EXPECT_EQ(q.sets.at("ZMAX").size(), 3u * 5 - 1 * 2);
  for (int i : q.sets.at("XMAX")) EXPECT_DOUBLE_EQ(q.nodes[i].x(), 0.01);
  const Job h = box({0.01, 0.01, 0.01}, {2, 2, 2}, "C3D8");
  EXPECT_EQ(h.nodes.size(), 27u);
  EXPECT_EQ(h.elements.size(), 8u);
  EXPECT_THROW(box({0, 1, 1}, {1, 1, 1}), std::invalid_argument);
  EXPECT_THROW(box({1, 1, 1}, {1, 0, 1}), std::invalid_argument);
  EXPECT_THROW(box({1, 1, 1}, {1, 1, 1}, "C3D4"), std::invalid_argument);
}

TEST(CalculiX, ABadJobIsNamed) {
  Job job = compressed("C3D8", {1, 1, 1}, 0.01, 0.9, {});
  job.material.poisson = 0.5;
  EXPECT_NE(tests::message_of<std::invalid_argument>([&] { input_file(job); }).find("Poisson"), std::string::npos);
  job.material.poisson = 0.3;
  job.elements[0].pop_back();
  EXPECT_NE(tests::message_of<std::invalid_argument>([&] { input_file(job); }).find("has 7 nodes"), std::string::npos);
  job = compressed("C3D8", {1, 1, 1}, 0.01, 0.9, {});
  job.fixes.push_back({"TOP", 3, 0});
  EXPECT_NE(tests::message_of<std::invalid_argument>([&] { input_file(job); }).find("set TOP"), std::string::npos);
  EXPECT_NE(tests::message_of<std::invalid_argument>([] { run(Job{}, "/tmp/it's"); }).find("quote"), std::string::npos);
}

// A homogeneous deformation is exact on any mesh: CalculiX must give the
// closed-form answer of its law, the neo-Hookean at 20 % compression with
// Poisson's ratio 0.45, and linear elasticity at 0.1 %.
TEST(CalculiX, AUniaxialCompressionIsTheClosedFormAnswer) {
  tests::TempDir dir;
  const double edge = 0.01, s = 0.8;
  for (const char* element : {"C3D8", "C3D20"}) {
    const Material soft{10000, 0.45, Law::neo_hookean};
    const Result r = run(compressed(element, {2, 2, 2}, edge, s, soft), (dir.path / element).string());
    const auto [t, sigma] = neo_hookean_uniaxial(soft.young, soft.poisson, s);
    const double force = sigma * (t * edge) * (t * edge);  // on the face as it is now
    EXPECT_NEAR(r.reaction.at("ZMAX").z() / force, 1, 1e-5) << element;
    const Job job = box(Eigen::Vector3d::Constant(edge), {2, 2, 2}, element);
    for (int i : job.sets.at("XMAX")) EXPECT_NEAR(r.displacement[i].x(), (t - 1) * edge, 1e-8) << element;
  }
  const Material linear{10000, 0.3, Law::linear};
  Job small = compressed("C3D20", {1, 1, 1}, edge, 0.999, linear);
  small.nlgeom = false;
  const Result r = run(small, (dir.path / "linear").string());
  EXPECT_NEAR(r.reaction.at("ZMAX").z() / (linear.young * -0.001 * edge * edge), 1, 1e-6);
  for (int i : small.sets.at("XMAX")) EXPECT_NEAR(r.displacement[i].x(), 0.3 * 0.001 * edge, 1e-12);
}

// A cantilever along x, clamped at x = 0, pulled down at its free end by
// `force` (N), its section h x h.
Job cantilever(double length, double h, std::array<int, 3> n, double force, Material m) {
  Job job = box({length, h, h}, n);
  job.material = m;
  job.fixes = {{"XMIN", 1, 0}, {"XMIN", 2, 0}, {"XMIN", 3, 0}};
  job.loads = {{"XMAX", 3, -force}};
  return job;
}

// The free end's mean displacement.
Eigen::Vector3d tip(const Job& job, const Result& r) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i : job.sets.at("XMAX")) sum += r.displacement[i];
  return sum / double(job.sets.at("XMAX").size());
}

// Euler's elastica of a cantilever under a dead end load: EI theta'' =
// -P cos(theta), theta(0) = 0, theta'(L) = 0, shot on theta'(0). Returns
// the end's drop and its pull-in toward the clamp, over L.
std::pair<double, double> elastica(double load) {  // load = P L^2 / EI
  const auto shoot = [&](double c, double* drop, double* pull) {
    const int steps = 4000;
    const double h = 1.0 / steps;
    double th = 0, w = c, x = 0, z = 0;  // on s in [0, 1]
    const auto f = [&](double t, double dw) {
      return std::array<double, 4>{dw, -load * std::cos(t), std::cos(t), std::sin(t)};
    };
    for (int i = 0; i < steps; ++i) {
      const auto k1 = f(th, w);
      const auto k2 = f(th + h / 2 * k1[0], w + h / 2 * k1[1]);
      const auto k3 = f(th + h / 2 * k2[0], w + h / 2 * k2[1]);
      const auto k4 = f(th + h * k3[0], w + h * k3[1]);
      th += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0]);
      w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1]);
      x += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
      z += h / 6 * (k1[3] + 2 * k2[3] + 2 * k3[3] + k4[3]);
    }
    if (drop) *drop = z, *pull = 1 - x;
    return w;  // theta'(L), to be 0
  };
  double lo = 0, hi = 2 * load;  // theta'(L) falls as theta'(0) rises
  for (int i = 0; i < 100; ++i) (shoot(0.5 * (lo + hi), nullptr, nullptr) > 0 ? hi : lo) = 0.5 * (lo + hi);
  double drop, pull;
  shoot(0.5 * (lo + hi), &drop, &pull);
  return {drop, pull};
}

// Bending, where linear hexahedra lock and quadratic ones do not: a
// slender cantilever's end deflects as beam theory says, by P L^3 / 3EI
// and the shear's P L / (k G A) at small load, and at large deflection
// (P L^2 / EI = 1, NLGEOM) as Euler's elastica, within 1 %.
TEST(CalculiX, ACantileverBendsAsBeamTheoryAndTheElasticaSay) {
  tests::TempDir dir;
  const double length = 0.1, h = 0.005, inertia = h * h * h * h / 12;
  const Material m{10000, 0.3, Law::linear};
  const double small = 1e-3 * m.young * inertia / (length * length);
  Job job = cantilever(length, h, {40, 2, 2}, small, m);
  job.nlgeom = false;
  const double shear = m.young / (2 * (1 + m.poisson));
  const double beam =
      small * std::pow(length, 3) / (3 * m.young * inertia) + small * length / (5.0 / 6 * shear * h * h);
  EXPECT_NEAR(-tip(job, run(job, (dir.path / "small").string())).z() / beam, 1, 0.01);

  const double large = m.young * inertia / (length * length);
  const Job bent = cantilever(length, h, {40, 2, 2}, large, m);
  const Eigen::Vector3d end = tip(bent, run(bent, (dir.path / "large").string()));
  const auto [drop, pull] = elastica(1);
  EXPECT_NEAR(-end.z() / (drop * length), 1, 0.01);
  EXPECT_NEAR(-end.x() / (pull * length), 1, 0.02);
}

}  // namespace
}  // namespace hcosim::adapters::reference
