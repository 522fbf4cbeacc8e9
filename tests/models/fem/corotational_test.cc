// The corotational FEM against analytic references: a bar in uniaxial
// tension (exact for linear tetrahedra), a cantilever converging to
// Timoshenko's beam under refinement; rigid motions cost nothing, an
// inverted element comes back, momentum is kept, a held node passes its
// elements' force, bad input is named.
#include "models/fem/corotational.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "tests/support/temp_dir.h"

namespace hcosim::models::fem {
namespace {

using models::massspring::PointForce;
using models::massspring::State;

// Steps until the mean z (or x) displacement of `nodes` changes by under
// 1e-10 of itself; returns it.
double settle(Corotational& f, State& s, const std::vector<PointForce>& loads, const std::vector<int>& nodes,
              int axis) {
  double last = 1e300, mean = 0;
  for (int k = 0; k < 500; ++k) {
    f.step(s, loads);
    mean = 0;
    for (const int i : nodes) mean += (s.x(axis, i) - f.mesh().rest(axis, i)) / double(nodes.size());
    if (std::abs(mean - last) <= 1e-10 * std::abs(mean)) break;
    last = mean;
  }
  return mean;
}

// Quasi-static: 1 s steps, damped on the mass.
Options quasi_static() {
  Options o;
  o.dt = 1;
  o.tolerance = 1e-10;
  return o;
}

// A 10 x 1 x 1 cm bar anchored at x = 0, with Poisson's ratio 0 so that the
// anchored end does not constrain it: uniaxial stress, strain F / (E A).
// The loads are the end's share of that stress field, the nodal forces
// that the field's own displacement needs; their sum must be sigma A.
TEST(FemCorotational, BarInTensionStretchesByFLOverEA) {
  const double E = 2e5, strain = 1e-4, L = 0.1, a = 0.01;
  Mesh m = box_mesh(21, 3, 3, a / 2);
  for (int i = 0; i < m.size(); ++i) m.anchored[i] = m.rest(0, i) < 1e-12;
  Material mat;
  mat.young = E, mat.poisson = 0, mat.alpha = 10;
  Corotational f(m, mat, quasi_static());
  State exact = rest_state(m);
  for (int i = 0; i < m.size(); ++i) exact.x(0, i) *= 1 + strain;
  std::vector<PointForce> loads;
  std::vector<int> end;
  double total = 0;
  for (int i = 0; i < m.size(); ++i) {
    const Eigen::Vector3d inner = f.force_on(i, exact);
    if (m.anchored[i]) continue;
    if (m.rest(0, i) > L - 1e-9) {
      loads.push_back({i, -inner});
      end.push_back(i);
      total += -inner.x();
    } else {
      EXPECT_LT(inner.norm(), 1e-9) << "node " << i << " inside the bar";  // the field is in equilibrium there
    }
  }
  EXPECT_NEAR(total, E * strain * a * a, 1e-9 * E * strain * a * a);
  State s = rest_state(m);
  EXPECT_NEAR(settle(f, s, loads, end, 0), strain * L, 1e-6 * strain * L);
  EXPECT_LT((s.x - exact.x).cwiseAbs().maxCoeff(), 1e-6 * strain * L);
}

// A 10 x 1 x 1 cm cantilever, its tip loaded downward: the tip's
// deflection approaches Timoshenko's P L^3 / (3 E I) + P L / (k G A) from
// below (linear tetrahedra are stiff in bending) as the mesh is refined,
// and its Richardson extrapolation is within 5 %.
TEST(FemCorotational, CantileverConvergesToBeamTheory) {
  const double L = 0.1, H = 0.01, E = 1e5, nu = 0.3, P = 1e-3;
  const double I = std::pow(H, 4) / 12, G = E / (2 * (1 + nu));
  const double beam = P * L * L * L / (3 * E * I) + P * L / (5.0 / 6 * G * H * H);
  std::vector<double> tip;
  for (int r = 1; r <= 4; ++r) {
    Mesh m = box_mesh(10 * r + 1, r + 1, r + 1, H / r);
    for (int i = 0; i < m.size(); ++i) m.anchored[i] = m.rest(0, i) < 1e-12;
    Material mat;
    mat.young = E, mat.poisson = nu, mat.alpha = 50;
    Corotational f(m, mat, quasi_static());
    std::vector<PointForce> loads;
    std::vector<int> end;
    for (int i = 0; i < m.size(); ++i)
      if (m.rest(0, i) > L - 1e-9) end.push_back(i);
    for (const int i : end) loads.push_back({i, Eigen::Vector3d(0, 0, -P / double(end.size()))});
    State s = rest_state(m);
    tip.push_back(-settle(f, s, loads, end, 2));
    std::printf("%d elements through the depth: tip %.3f of the beam's\n", r, tip.back() / beam);
    if (r > 1) {
      EXPECT_GT(tip[r - 1], tip[r - 2]) << "refinement " << r;
    }
    EXPECT_LT(tip.back(), beam) << "refinement " << r;
  }
  EXPECT_GT(tip.back(), 0.85 * beam);
  const double extrapolated = tip[3] + (tip[3] - tip[2]) / (16.0 / 9 - 1);
  std::printf("Richardson extrapolation: %.3f of the beam's\n", extrapolated / beam);
  EXPECT_NEAR(extrapolated / beam, 1, 0.05);
}

// A rigid rotation and translation of a deformed-free box costs nothing
// and exerts nothing; a stretched box's energy is the same rotated.
TEST(FemCorotational, RigidMotionsCostNothing) {
  const Mesh m = box_mesh(3, 3, 3, 0.01);
  Corotational f(m, {}, {});
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(2.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  State s = rest_state(m);
  s.x = (Q * m.rest).colwise() + Eigen::Vector3d(0.3, -0.2, 0.1);
  EXPECT_LT(f.energy(s.x), 1e-18);
  for (int i = 0; i < m.size(); ++i) EXPECT_LT(f.force_on(i, s).norm(), 1e-9) << i;
  Eigen::Matrix3Xd stretched = m.rest;
  stretched.row(2) *= 1.1;
  const double e = f.energy(stretched);
  EXPECT_GT(e, 0);
  EXPECT_NEAR(f.energy(Q * stretched), e, 1e-9 * e);
}

class FemCorotationalPerScheme : public ::testing::TestWithParam<Scheme> {};

// One tetrahedron on its anchored base, its apex pushed through the base
// (inverted): the elements push it back to its rest volume's side.
TEST_P(FemCorotationalPerScheme, AnInvertedElementComesBack) {
  Mesh m;
  m.rest.resize(3, 4);
  m.rest << 0, 0.01, 0, 0.002, 0, 0, 0.01, 0.003, 0, 0, 0, 0.01;
  m.tets = {{0, 1, 2, 3}};
  m.anchored = {1, 1, 1, 0};
  Material mat;
  mat.alpha = 20;
  Options o;
  o.dt = 1e-3;
  o.scheme = GetParam();
  Corotational f(m, mat, o);
  State s = rest_state(m);
  s.x(2, 3) = -0.005;
  for (int k = 0; k < 2000; ++k) f.step(s, {});
  EXPECT_NEAR(s.x(2, 3), 0.01, 1e-5);
}

// A whole free box mirrored through its centre (every element inverted),
// and one collapsed to a point, under each implicit scheme: the elements
// bring it back to its rest shape (every edge within 1 % of its length,
// every volume within 3 %), which the mass-spring lattice under implicit
// integration does not (docs/massspring.md, "Volume floors").
TEST_P(FemCorotationalPerScheme, AnInvertedOrCollapsedBoxComesBack) {
  const Mesh m = box_mesh(4, 4, 4, 0.01);
  Material mat;
  mat.alpha = 20;
  Options o;
  o.scheme = GetParam();
  Corotational f(m, mat, o);
  const Eigen::Vector3d centre(0.015, 0.015, 0.015);
  for (const bool inverted : {true, false}) {
    State s = rest_state(m);
    for (int i = 0; i < m.size(); ++i) s.x.col(i) = inverted ? Eigen::Vector3d(2 * centre - m.rest.col(i)) : centre;
    for (int k = 0; k < 3000; ++k) f.step(s, {});
    double stretch = 0, squash = 1;
    auto volume = [](const Eigen::Matrix3Xd& x, const std::array<int, 4>& t) {
      return (x.col(t[1]) - x.col(t[0])).dot((x.col(t[2]) - x.col(t[0])).cross(x.col(t[3]) - x.col(t[0])));
    };
    for (const auto& t : m.tets) {
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < p; ++q) {
          const double rest = (m.rest.col(t[p]) - m.rest.col(t[q])).norm();
          stretch = std::max(stretch, std::abs((s.x.col(t[p]) - s.x.col(t[q])).norm() - rest) / rest);
        }
      squash = std::min(squash, volume(s.x, t) / volume(m.rest, t));
    }
    EXPECT_LT(stretch, 0.01) << (inverted ? "inverted" : "collapsed");
    EXPECT_GT(squash, 0.97) << (inverted ? "inverted" : "collapsed");
  }
}

// Nothing anchored, no loads: internal forces cancel, momentum stays.
TEST_P(FemCorotationalPerScheme, MomentumIsKept) {
  const Mesh m = box_mesh(3, 3, 3, 0.01);
  Material mat;
  mat.beta = 1e-3;
  Options o;
  o.scheme = GetParam();
  Corotational f(m, mat, o);
  State s = rest_state(m);
  for (int i = 0; i < m.size(); ++i) s.v.col(i) = Eigen::Vector3d(std::sin(i), std::cos(3 * i), 0.1 * i);
  auto momentum = [&] {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < m.size(); ++i) p += f.mass()[i] * s.v.col(i);
    return p;
  };
  const Eigen::Vector3d p0 = momentum();
  for (int k = 0; k < 100; ++k) f.step(s, {});
  EXPECT_LT((momentum() - p0).norm(), 1e-6 * p0.norm());
  EXPECT_NEAR(f.mass().sum(), 1000 * 0.02 * 0.02 * 0.02, 1e-12);
}

// A top node held 1 mm down on a box anchored at its base: it stays where
// it is held, and what holds it feels the elements' push, upward.
TEST_P(FemCorotationalPerScheme, AHeldNodeStaysAndFeelsItsElements) {
  Mesh m = box_mesh(3, 3, 3, 0.01);
  for (int i = 0; i < m.size(); ++i) m.anchored[i] = m.rest(2, i) < 1e-12;
  Material mat;
  mat.alpha = 10;
  Options o = quasi_static();
  o.scheme = GetParam();
  Corotational f(m, mat, o);
  const int top = 4 + 9 * 2;
  f.hold(top, true);
  State s = rest_state(m);
  s.x(2, top) -= 0.001;
  for (int k = 0; k < 50; ++k) f.step(s, {});
  EXPECT_DOUBLE_EQ(s.x(2, top), m.rest(2, top) - 0.001);
  EXPECT_GT(f.force_on(top, s).z(), 0);
  EXPECT_THROW(f.hold(0, true), std::invalid_argument);  // anchored
}

// A box on its anchored base rings, undamped, after a sideways kick of its
// top: over 1000 steps (about 10 periods of its first mode) the
// trapezoidal rule keeps the energy of the vibration, implicit Euler
// drains it.
TEST_P(FemCorotationalPerScheme, AnUndampedVibrationKeepsItsEnergyUnderTheTrapezoidalRule) {
  Mesh m = box_mesh(3, 3, 4, 0.01);
  for (int i = 0; i < m.size(); ++i) m.anchored[i] = m.rest(2, i) < 1e-12;
  Options o;
  o.dt = 1e-4;
  o.scheme = GetParam();
  Corotational f(m, {}, o);
  State s = rest_state(m);
  for (int i = 0; i < m.size(); ++i)
    if (!m.anchored[i]) s.v(0, i) = 0.01 * m.rest(2, i) / 0.03;
  auto energy = [&] {
    double e = f.energy(s.x);
    for (int i = 0; i < m.size(); ++i) e += 0.5 * f.mass()[i] * s.v.col(i).squaredNorm();
    return e;
  };
  const double e0 = energy();
  for (int k = 0; k < 1000; ++k) f.step(s, {});
  std::printf("energy after 1000 steps: %.4f of the kick's\n", energy() / e0);
  if (GetParam() == Scheme::trapezoidal) {
    EXPECT_NEAR(energy() / e0, 1, 0.01);
  } else {
    EXPECT_LT(energy() / e0, 0.98);
  }
}

INSTANTIATE_TEST_SUITE_P(, FemCorotationalPerScheme, ::testing::Values(Scheme::implicit_euler, Scheme::trapezoidal),
                         [](const auto& p) {
                           return std::string(p.param == Scheme::trapezoidal ? "trapezoidal" : "implicit_euler");
                         });

TEST(FemCorotational, BadInputIsNamed) {
  const Mesh m = box_mesh(2, 2, 2, 0.01);
  auto message = [&](Mesh mesh, Material mat, Options o) {
    return tests::message_of([&] { Corotational f(std::move(mesh), mat, o); });
  };
  Material mat;
  mat.poisson = 0.5;
  EXPECT_NE(message(m, mat, {}).find("Poisson"), std::string::npos);
  mat = {};
  mat.young = 0;
  EXPECT_NE(message(m, mat, {}).find("Young"), std::string::npos);
  Mesh bad = m;
  bad.tets[0][1] = bad.tets[0][0];
  EXPECT_NE(message(bad, {}, {}).find("tetrahedron 0 repeats"), std::string::npos);
  bad = m;
  bad.rest.col(bad.tets[2][3]) = bad.rest.col(bad.tets[2][0]);
  EXPECT_NE(message(bad, {}, {}).find("no volume"), std::string::npos);
  Corotational f(m, {}, {});
  State s = rest_state(m);
  s.x(0, 0) = NAN;
  EXPECT_NE(tests::message_of([&] { f.step(s, {}); }).find("finite"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::models::fem
