// Seed 000's elastic surfaces touched through a proxy, judged as the hand
// would: the sheet pushes back and recovers, a stroke feels no more than
// its friction, a press between nodes is felt along the normal, the force
// felt is the load the surface takes, contact starts without a kick and a
// hold is steady; on both shapes.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "models/deformable/elastic_surface.h"
#include "models/deformable/surface.h"

namespace hcosim::models::deformable {
namespace {

constexpr double kDt = 1e-3;  // s, the servo period

SurfaceSpec sheet_spec(haptic::Friction f = {0.3, 0.3}) {
  SurfaceSpec s;
  s.options.dt = kDt;
  s.friction = f;
  return s;
}

// Stiffer than the default membrane and with bending springs: the default
// dome folds inward around a held press, away from the stylus (a membrane
// without shape memory, issue 26). Even this one turns its top inside out
// under a few millimetres, so its presses stay shallower. These tests
// judge the contact, not the shell.
SurfaceSpec dome_spec(haptic::Friction f = {0.3, 0.3}) {
  SurfaceSpec s = sheet_spec(f);
  s.material.k = 1000;
  s.bending = 3;
  s.shape = Shape::semisphere;
  s.resolution = 12;
  s.size = 0.03;
  return s;
}

// Tangential over normal part of a force, against unit normal n.
double ratio(const Eigen::Vector3d& f, const Eigen::Vector3d& n) {
  const double push = f.dot(n);
  return (f - push * n).norm() / push;
}

TEST(ElasticSurface, SheetPressedPushesBackAndRecovers) {  // 000 §2.2
  ElasticSurface sheet(sheet_spec());
  EXPECT_FALSE(sheet.touch(kDt, Eigen::Vector3d(0, 0, 0.01), false).in_contact);
  double last = 0;
  Touch t;
  for (int k = 1; k <= 700; ++k) {
    t = sheet.touch(kDt, Eigen::Vector3d(0.0013, 0.0007, 0.002 - 0.012 * std::min(1.0, k / 200.0)), false);
    if (k >= 40 && k <= 200 && k % 40 == 0) {
      EXPECT_GT(t.force.z(), last) << k;
      last = t.force.z();
    }
  }
  ASSERT_TRUE(t.in_contact);
  EXPECT_NEAR(t.depth, 0.01, 1e-9);
  // The proxy is on the surface, above the HIP by the coupling's stretch.
  const Eigen::Vector3d hip(0.0013, 0.0007, -0.01);
  EXPECT_NEAR((sheet.proxy() - hip).z(), t.force.z() / sheet_spec().contact_stiffness, 2e-4);
  for (int k = 0; k < 5000; ++k) sheet.touch(kDt, Eigen::Vector3d(0, 0, 0.05), false);
  EXPECT_EQ(sheet.contact().face, -1);
  EXPECT_LT((sheet.state().x - sheet.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_THROW(sheet.touch(2e-3, Eigen::Vector3d::Zero(), false), std::invalid_argument);
}

// The first HIP seen under the sheet (a service started with the stylus
// pressing it) touches at the nearest point; over it, nothing.
TEST(ElasticSurface, AFirstHipBehindTheSurfaceTouchesItsNearestPoint) {
  ElasticSurface under(sheet_spec());
  const Touch t = under.touch(kDt, Eigen::Vector3d(0.0011, 0.0023, -0.002), false);
  EXPECT_TRUE(t.in_contact);
  EXPECT_GT(t.force.z(), 0);
  ElasticSurface over(sheet_spec());
  EXPECT_FALSE(over.touch(kDt, Eigen::Vector3d(0.0011, 0.0023, 0.002), false).in_contact);
}

TEST(ElasticSurface, SemiSphereDentsInwardAndItsMeshFacesOutward) {
  ElasticSurface dome(dome_spec());
  const Eigen::Matrix3Xd x = dome.surface();
  double flux = 0;
  const Eigen::Matrix3Xd n = vertex_normals(x, dome.triangles());
  for (int i = 0; i < n.cols(); ++i) flux += n.col(i).dot(x.col(i));
  EXPECT_GT(flux, 0);
  Touch t;
  for (int k = 1; k <= 400; ++k)
    t = dome.touch(kDt, Eigen::Vector3d(0, 0, 0.032 - 0.0035 * std::min(1.0, k / 200.0)), false);
  EXPECT_TRUE(t.in_contact);
  EXPECT_GT(t.force.z(), 0);
  EXPECT_LT(dome.state().x.row(2).minCoeff(), 0.03);
  EXPECT_TRUE(dome.state().x.allFinite());
}

// Both shapes, each with a stroke over its surface: at(s, depth) is the
// HIP at arc length s (m) along the stroke, `depth` (m) inside the rest
// surface (negative: outside), and normal(s) the rest surface's outward
// normal there. Both start between nodes.
struct Case {
  std::string name;
  SurfaceSpec (*spec)(haptic::Friction);
  Eigen::Vector3d (*at)(double s, double depth);
  Eigen::Vector3d (*normal)(double s);
  double stroke;  // m, how far a stroke goes
  double depth;   // m, how deep its presses go
};

Eigen::Vector3d dome_normal(double s) {
  return Eigen::Vector3d(0.04, std::sin(s / 0.03), std::cos(s / 0.03)).normalized();
}

const Case kCases[] = {
    {"sheet", sheet_spec, [](double s, double depth) { return Eigen::Vector3d(0.0011 + s, 0.0023, -depth); },
     [](double) -> Eigen::Vector3d { return Eigen::Vector3d::UnitZ(); }, 0.02, 0.003},
    {"semisphere", dome_spec, [](double s, double depth) { return Eigen::Vector3d((0.03 - depth) * dome_normal(s)); },
     dome_normal, 0.01, 0.0015},
};

// In from 2 mm outside to `depth` in `ramp` ticks, then held for `hold`.
Touch press(ElasticSurface& o, const Case& c, double depth, int ramp, int hold) {
  Touch t;
  for (int k = 0; k <= ramp + hold; ++k)
    t = o.touch(kDt, c.at(0, -0.002 + (0.002 + depth) * std::min(1.0, double(k) / ramp)), false);
  return t;
}

class SurfaceContact : public ::testing::TestWithParam<Case> {};

// Press, then slide at 1 cm/s: while slipping, the force leans
// no more than the dynamic coefficient (+0.02) off the normal, and it does
// slip.
TEST_P(SurfaceContact, AStrokeFeelsItsFrictionAndNoMore) {
  const Case& c = GetParam();
  for (const haptic::Friction f : {haptic::Friction{0.5, 0.3}, haptic::Friction{0, 0}}) {
    ElasticSurface o(c.spec(f));
    Touch t = press(o, c, c.depth, 300, 200);
    ASSERT_TRUE(t.in_contact) << c.name;
    double most = 0, felt = 0;
    int ticks = 0;
    for (int k = 1; k <= int(c.stroke / 1e-5); ++k) {
      t = o.touch(kDt, c.at(1e-5 * k, c.depth), false);
      ASSERT_TRUE(t.in_contact) << c.name << " tick " << k;
      if (k < 500) continue;  // the stroke's onset, before it slips
      most = std::max(most, ratio(t.force, t.normal));
      felt += ratio(t.force, t.normal), ++ticks;
    }
    EXPECT_LE(most, f.dynamic_mu + 0.02) << c.name << " mu " << f.dynamic_mu;
    EXPECT_GE(felt / ticks, 0.8 * f.dynamic_mu) << c.name << " mu " << f.dynamic_mu;
  }
}

// Frictionless, entering a face between its nodes: the force is along the
// touched face's normal, and while the dent is shallow (0.5 mm), along the
// rest surface's.
TEST_P(SurfaceContact, EnteringBetweenNodesIsFeltAlongTheNormal) {
  const Case& c = GetParam();
  ElasticSurface o(c.spec({0, 0}));
  double off_face = 0, off_rest = 0;
  int touched = 0, in = 0;
  for (int k = 0; k <= 600; ++k) {
    const double depth = -0.002 + (0.002 + c.depth) * std::min(1.0, k / 300.0);
    const Touch t = o.touch(kDt, c.at(0, depth), false);
    in += depth > 0;
    if (!t.in_contact) continue;
    ++touched;
    if (t.force.isZero()) continue;
    auto angle = [&](const Eigen::Vector3d& n) { return std::acos(std::min(1.0, t.force.normalized().dot(n))); };
    off_face = std::max(off_face, angle(t.normal));
    if (depth <= 5e-4) off_rest = std::max(off_rest, angle(c.normal(0)));
  }
  EXPECT_GE(touched, in - 10) << c.name;            // from the tick it crosses the surface on
  EXPECT_LT(off_face * 180 / M_PI, 0.5) << c.name;  // the tick's substeps' normals differ a little
  EXPECT_LT(off_rest * 180 / M_PI, 5) << c.name;
}

// Every tick the surface takes the opposite of the force felt, and the
// first tick of contact is no harder than the coupling times its motion.
TEST_P(SurfaceContact, TheForceFeltIsTheLoadTakenAndStartsWithoutAKick) {
  const Case& c = GetParam();
  ElasticSurface o(c.spec({0.4, 0.3}));
  const double k_c = c.spec({0, 0}).contact_stiffness;
  bool touched = false;
  Eigen::Vector3d last = c.at(0, -0.002);
  for (int k = 0; k <= 1500; ++k) {
    // In at 5 cm/s, a stroke, and out.
    const double deep = 0.002 + c.depth;
    const double in = k < 800 ? std::min(deep, 5e-5 * k) : std::max(-0.003, deep - 5e-5 * (k - 800));
    const Eigen::Vector3d hip = c.at(k > 300 ? 1e-5 * (k - 300) : 0, in - 0.002);
    const Touch t = o.touch(kDt, hip, false);
    Eigen::Vector3d taken = Eigen::Vector3d::Zero();
    for (const models::massspring::PointForce& p : o.loads()) taken += p.force;
    EXPECT_LE((taken + t.force).norm(), 1e-12 * (1 + t.force.norm())) << c.name << " tick " << k;
    if (t.in_contact && !touched) {
      EXPECT_LE(t.force.norm(), k_c * (hip - last).norm() * (1 + 1e-9)) << c.name;
    }
    touched = touched || t.in_contact;
    last = hip;
  }
  EXPECT_TRUE(touched) << c.name;
  EXPECT_EQ(o.contact().face, -1) << c.name;
}

// A press held still: the force's spread over 0.5 s is under 2 % of it.
TEST_P(SurfaceContact, AHoldIsSteady) {
  const Case& c = GetParam();
  ElasticSurface o(c.spec({0.3, 0.3}));
  press(o, c, c.depth, 200, 800);  // the membrane rings for a while after the press
  double sum = 0, square = 0;
  for (int k = 0; k < 500; ++k) {
    const double f = o.touch(kDt, c.at(0, c.depth), false).force.norm();
    sum += f, square += f * f;
  }
  const double mean = sum / 500, spread = std::sqrt(std::max(0.0, square / 500 - mean * mean));
  EXPECT_GT(mean, 0) << c.name;
  EXPECT_LT(spread, 0.02 * mean) << c.name;
}

INSTANTIATE_TEST_SUITE_P(, SurfaceContact, ::testing::ValuesIn(kCases), [](const auto& p) { return p.param.name; });

}  // namespace
}  // namespace hcosim::models::deformable
