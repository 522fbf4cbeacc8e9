// The hybrid deformable model (001): the visual map, release, monotone and
// non-homogeneous force, agreement of the force felt with the behavior
// model's, organs from a mesh, friction, and abuse by the haptic point.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "models/deformable/hybrid.h"
#include "models/deformable/surface.h"
#include "tests/support/shapes.h"

namespace hcosim::models::deformable {
namespace {

// A force gain for tests of what does not depend on the force's size (the
// map, the placing of a shape): computing the real one settles the
// behavior model dozens of times, which takes seconds, a minute under the
// sanitizers.
GainSource any_gain() {
  return [](const HybridSpec&, const Weights&) {
    ForceGain g;
    g.depth = {1e-3, 1e-2}, g.soft = {0.1, 1}, g.soft_compliance = 1e-2;
    return g;
  };
}

// The top-face element above the centre, offset by (dx, dy) elements.
int top(const HybridSpec& s, int dx = 0, int dy = 0) {
  const int n = s.elements;
  return (n / 2 + dx) + n * ((n / 2 + dy) + n * (n - 1));
}

// From 1 mm above element e's rest point (on the top face, where the drawn
// surface touches it), `depth` down into it over 100 ticks, held 200.
Touch press(Hybrid& h, int e, double depth) {
  const Eigen::Vector3d r = h.haptic().lattice().rest(e);
  Touch t;
  for (int k = 0; k < 300; ++k) {
    t = h.touch(1e-3, r + Eigen::Vector3d(0, 0, 0.001 - (0.001 + depth) * std::min(1.0, (k + 1) / 100.0)), false);
    h.advance();
  }
  return t;
}

// The seed's visual mesh has face centres a rounding error off its cage's
// faces, where the closed mean value formula once lost 3 cm.
class HybridVisualMap : public ::testing::TestWithParam<VisualMap> {};

TEST_P(HybridVisualMap, SeedVisualMeshFollowsAffineCageMotions) {
  const VisualMap m = GetParam();
  HybridSpec s;
  s.map = m;
  const Hybrid h(s, {}, any_gain());
  const models::massspring::Lattice& lat = h.behavior().lattice();
  Eigen::Matrix3d a;
  a << 1.1, 0.2, 0, -0.1, 0.9, 0.05, 0.02, 0, 1.05;
  const Eigen::Vector3d b(0.01, -0.02, 0.03);
  const std::vector<int>& cage = h.cage_masses();
  Eigen::Matrix3Xd x(3, cage.size());
  for (std::size_t i = 0; i < cage.size(); ++i) x.col(i) = a * lat.rest.col(cage[i]) + b;
  const Eigen::Matrix3Xd expect = (a * h.visual_rest().vertices).colwise() + b;
  // Truncation keeps 0.999 of each row: linear precision to about that;
  // points within 1e-7 of the cage's size from a face take their projection's.
  EXPECT_LT((apply(h.map(), x) - expect).cwiseAbs().maxCoeff(), m == VisualMap::mvc_sparse ? 2e-4 : 1e-7);
}

std::string map_name(const ::testing::TestParamInfo<VisualMap>& i) { return name(i.param); }
INSTANTIATE_TEST_SUITE_P(, HybridVisualMap, ::testing::Values(VisualMap::mvc_sparse), map_name);
INSTANTIATE_TEST_SUITE_P(Slow, HybridVisualMap, ::testing::Values(VisualMap::mvc, VisualMap::trilinear), map_name);

TEST(HybridSlow, ReleaseReturnsToTheRestShape) {
  HybridSpec s;
  Hybrid h(s);
  const Touch t = press(h, top(s), 0.005);
  EXPECT_TRUE(t.in_contact);
  EXPECT_GT(h.simulated(), 0);
  EXPECT_GT((h.surface() - h.visual_rest().vertices).cwiseAbs().maxCoeff(), 1e-3);
  for (int k = 0; k < 3000; ++k) h.touch(1e-3, s.centre + Eigen::Vector3d(0, 0, 0.2), false), h.advance();
  EXPECT_TRUE(h.haptic().moved().empty());
  EXPECT_LT((h.state().x - h.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_LT((h.surface() - h.visual_rest().vertices).cwiseAbs().maxCoeff(), 1e-5);
}

// Tests that do not concern the visual map use the one that costs nothing to build.
HybridSpec quick() {
  HybridSpec s;
  s.map = VisualMap::trilinear;
  return s;
}

TEST(HybridSlow, ForceGrowsMonotonicallyWithDepth) {
  const HybridSpec s = quick();
  double last = 0;
  for (double depth = 0.001; depth <= 0.02; depth += 0.00125) {
    Hybrid h(s);
    const Touch t = press(h, top(s), depth);
    EXPECT_GT(t.force.z(), last) << "depth " << depth;
    EXPECT_NEAR(t.depth, depth, 1e-8);
    EXPECT_GT(t.stiffness, 0);
    last = t.force.z();
  }
}

TEST(HybridSlow, StifferSidePushesBackHarderInBothModels) {  // 001 Fig 8
  HybridSpec s = quick();
  s.stiff_ratio = 4;
  Hybrid soft(s), hard(s);
  // The middle of each half's top, where the drawn surface is as far
  // below the lattice's top on both sides.
  const double f_soft = press(soft, top(s, -3), 0.004).force.z();
  const double f_hard = press(hard, top(s, 2), 0.004).force.z();
  EXPECT_GT(f_hard, 2 * f_soft);
  const Eigen::Vector3d down(0, 0, -0.004);
  EXPECT_GT(behavior_static_force(s, top(s, 2), down).z(), 2 * behavior_static_force(s, top(s, -3), down).z());
}

// The force felt agrees with the shape seen, here at
// each side's gain point: pressed from 0.5 mm to a quarter of its size
// below the drawn surface there and held 0.9 s, the hybrid's force is
// within 15 % of the behavior model's static force for a press of its
// drawn surface at that depth (behavior_surface_force, settled afresh).
// What this checks is the path from calibration to hand: the S-Chain's
// relaxation, the scale between the gain's depths, the contact landing on
// the point, and follow() settling with the behavior model, which rings
// under a deep press of the stiff side for a few tenths of a second.
// Elsewhere follow() brings the force to the behavior model's own
// (WhatIsSeenFollowsWhatIsFeltAllOverAnOrgan). The S-Chain alone, fitted
// on 1 to 5 mm, pushes 8.7 to 15.7 times harder by 25 mm (bench hybrid,
// force_vs_behavior).
TEST(HybridSlow, ForceFeltAgreesWithTheBehaviorModelToAQuarterOfItsSize) {
  HybridSpec s = quick();
  s.stiff_ratio = 4;
  const std::vector<double> depths{0.0005, 0.00075, 0.0015, 0.0035, 0.007, 0.011, 0.015, 0.019, 0.023, 0.025};
  for (const bool stiff : {false, true}) {
    Hybrid h(s);
    // Down to the drawn surface at the side's gain point, then `depth`
    // under it, and back up and let go.
    const Eigen::Vector3d r = h.gain_point(stiff);
    Touch t;
    double z = r.z() + 0.001;
    while (!(t = h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), z), false)).in_contact) h.advance(), z -= 1e-5;
    const double surface = h.proxy().z();
    const std::vector<double> behavior = behavior_surface_force(s, h.proxy(), depths);
    for (std::size_t j = 0; j < depths.size(); ++j) {
      for (int k = 0; k < 1000; ++k) h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), surface + 0.002), false), h.advance();
      for (int k = 0; k < 1000; ++k) {
        t = h.touch(
            1e-3, Eigen::Vector3d(r.x(), r.y(), surface + 0.001 - (0.001 + depths[j]) * std::min(1.0, (k + 1) / 100.0)),
            false);
        h.advance();
      }
      EXPECT_NEAR(t.force.z() / behavior[j], 1, 0.15) << (stiff ? "stiff" : "soft") << " side, depth " << depths[j]
                                                      << ": felt " << t.force.z() << " N, behavior " << behavior[j];
    }
  }
}

// With the corotational FEM as its behavior model (a 6^3 cube, to be
// quick), the force felt 3 mm under the drawn surface is the FEM's static
// force there within 15 % (the force gain is the FEM's), the FEM takes the
// load and deforms, and it comes back to rest once let go.
TEST(Hybrid, AFemBehaviorModelIsFeltAsItsStaticForceAndComesBack) {
  HybridSpec s = quick();
  s.elements = 6;
  s.behavior_model = BehaviorModel::fem;
  Hybrid h(s);
  const Eigen::Vector3d r = h.haptic().lattice().rest(top(s));
  Touch t;
  double z = r.z() + 0.001;
  while (!(t = h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), z), false)).in_contact) h.advance(), z -= 1e-5;
  const double surface = h.proxy().z(), depth = 0.003;
  for (int k = 0; k < 300; ++k) {
    t = h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), surface - depth * std::min(1.0, (k + 1) / 100.0)), false);
    h.advance();
  }
  const double fem = behavior_surface_force(s, h.proxy(), {depth})[0];
  EXPECT_NEAR(t.force.z() / fem, 1, 0.15) << "felt " << t.force.z() << " N, FEM " << fem << " N";
  EXPECT_LT(h.state().x.col(top(s)).z(), h.behavior().lattice().rest.col(top(s)).z() - 0.5 * depth);
  for (int k = 0; k < 2000; ++k) h.touch(1e-3, s.centre + Eigen::Vector3d(0, 0, 0.2), false), h.advance();
  EXPECT_LT((h.state().x - h.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_EQ(parse_behavior_model("fem"), BehaviorModel::fem);
  EXPECT_THROW(parse_behavior_model("jelly"), std::invalid_argument);
}

// With the FEM's lowest modes as its behavior model, the same: felt as
// its static force, deformed under the load, back at rest once let go;
// and a small press (0.5 mm, where rotations do not matter) statically
// as stiff as the corotational FEM's with every mode, stiffer with fewer.
TEST(Hybrid, AModalBehaviorModelIsFeltAsItsStaticForceAndComesBack) {
  HybridSpec s = quick();
  s.elements = 6;
  s.behavior_model = BehaviorModel::modal;
  s.modes = 16;
  Hybrid h(s);
  const Eigen::Vector3d r = h.haptic().lattice().rest(top(s));
  Touch t;
  double z = r.z() + 0.001;
  while (!(t = h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), z), false)).in_contact) h.advance(), z -= 1e-5;
  const double surface = h.proxy().z(), depth = 0.003;
  for (int k = 0; k < 300; ++k) {
    t = h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), surface - depth * std::min(1.0, (k + 1) / 100.0)), false);
    h.advance();
  }
  const double modal = behavior_surface_force(s, h.proxy(), {depth})[0];
  EXPECT_NEAR(t.force.z() / modal, 1, 0.15) << "felt " << t.force.z() << " N, modal " << modal << " N";
  EXPECT_LT(h.state().x.col(top(s)).z(), h.behavior().lattice().rest.col(top(s)).z() - 0.5 * depth);
  for (int k = 0; k < 2000; ++k) h.touch(1e-3, s.centre + Eigen::Vector3d(0, 0, 0.2), false), h.advance();
  EXPECT_LT((h.state().x - h.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_EQ(parse_behavior_model("modal"), BehaviorModel::modal);

  const Eigen::Vector3d small(0, 0, -5e-4);
  HybridSpec all = s, fem = s;
  all.modes = 3 * (s.elements * s.elements * (s.elements - 1));  // every free node's
  fem.behavior_model = BehaviorModel::fem;
  const double f_all = behavior_static_force(all, top(s), small).z(),
               f_fem = behavior_static_force(fem, top(s), small).z();
  EXPECT_NEAR(f_all / f_fem, 1, 0.01) << "every mode " << f_all << " N, FEM " << f_fem << " N";
  EXPECT_GT(behavior_static_force(s, top(s), small).z(), f_all);
}

TEST(Hybrid, FarAndNanPointsAndAZeroStepAreHandled) {
  const HybridSpec s = quick();
  Hybrid h(s);
  EXPECT_FALSE(h.touch(1e-3, Eigen::Vector3d(1e3, -1e3, 1e3), false).in_contact);
  EXPECT_THROW(h.touch(1e-3, Eigen::Vector3d(NAN, 0, 0), false), std::invalid_argument);
  EXPECT_THROW(h.touch(0, s.centre, false), std::invalid_argument);
  // A path from far away through the surface touches; so does the first
  // HIP seen inside (a service started with the stylus in the object), at
  // the nearest surface point.
  EXPECT_TRUE(h.touch(1e-3, s.centre, false).in_contact);
  Hybrid fresh(s);
  const Eigen::Vector3d below_top = s.centre + Eigen::Vector3d(0.001, 0.002, 0.5 * s.size - 0.004);
  const Touch t = fresh.touch(1e-3, below_top, false);
  EXPECT_TRUE(t.in_contact);
  EXPECT_NEAR(t.depth, 0.004, 1e-9);
  EXPECT_NEAR((fresh.proxy() - below_top).z(), 0.004, 1e-9);
}

// An organ-like 3 cm ellipsoid in its cage, the +x half four times stiffer
// (001 Fig 8).
HybridSpec organ(haptic::Friction f = {0.3, 0.3}) {
  HybridSpec s;
  s.size = 0.03;
  s.centre = Eigen::Vector3d(0.05, -0.035, 0.015);
  s.visual_exponent = 2;
  s.stiff_ratio = 4;
  s.map = VisualMap::trilinear;
  s.friction = f;
  return s;
}

// Unit direction from the organ's centre, and the distance along it to the
// drawn ellipsoid (its semi-axes are half the cage's edge).
Eigen::Vector3d direction(int k, int of) {
  const double z = 1 - (2 * k + 1.0) / of, r = std::sqrt(1 - z * z), phi = k * 2.399963;  // golden angle
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Touched from 100 directions (the lower half too: the anchored bottom is
// drawn as well), coming in at 0.05 mm a tick: contact begins within
// 0.5 mm of the drawn surface (of it grown by the tip's radius, for a tip
// of 2 mm), never at the cage's box.
TEST(HybridSlow, TheOrganIsTouchedWhereItsSurfaceIsDrawn) {
  for (const double tip : {0.0, 0.002}) {
    HybridSpec s = organ();
    s.tip_radius = tip;
    Hybrid h(s);
    const double half = 0.5 * s.size;
    for (int k = 0; k < 100; ++k) {
      const Eigen::Vector3d d = direction(k, 100);
      double at = -1;
      for (double r = 1.2 * std::sqrt(3) * half; r > 0 && at < 0; r -= 5e-5)
        if (h.touch(1e-3, s.centre + r * d, false).in_contact) at = r;
      for (int n = 0; n < 3; ++n) h.touch(1e-3, s.centre + 2 * half * std::sqrt(3) * d, false);  // out again
      ASSERT_GT(at, 0) << "no contact along " << d.transpose();
      EXPECT_NEAR(at, half + tip, 5e-4) << "along " << d.transpose() << ", tip radius " << tip;
    }
  }
}

// An organ from a mesh: the loaf scaled to 4 cm and put on the floor.
HybridSpec loaf_spec() {
  HybridSpec s;
  s.shape = tests::loaf();
  s.size = 0.04;
  s.elements = 16;
  s.centre = Eigen::Vector3d(0.01, -0.02, 0.008);  // its box is 1.6 cm high
  s.friction = {0.5, 0.5};
  return s;
}

TEST(HybridShape, AnOrganIsItsMeshPlacedAndFilledByItsCells) {
  const HybridSpec s = loaf_spec();
  const Hybrid h(s, {}, any_gain());
  const models::massspring::TriangleMesh& v = h.visual_rest();
  EXPECT_EQ(v.vertices.cols(), tests::loaf().vertices.cols());
  EXPECT_EQ(v.triangles, tests::loaf().triangles);
  const Eigen::Vector3d lo = v.vertices.rowwise().minCoeff(), hi = v.vertices.rowwise().maxCoeff();
  EXPECT_NEAR((hi - lo).maxCoeff(), 0.04, 1e-12);
  EXPECT_LT((0.5 * (lo + hi) - s.centre).norm(), 1e-12);
  EXPECT_NEAR(lo.z(), 0, 1e-12);
  EXPECT_GT(tests::signed_volume(v.vertices, v.triangles), 0);
  // Masses only where cells are inside: within a cell's diagonal of the
  // surface's box, far fewer than the box's nodes, the floor's anchored.
  const models::massspring::Lattice& l = h.behavior().lattice();
  const double cell = 0.04 / 15;
  int anchored = 0;
  for (int i = 0; i < l.size(); ++i) {
    EXPECT_TRUE((l.rest.col(i).array() > lo.array() - cell).all() && (l.rest.col(i).array() < hi.array() + cell).all());
    if (!l.anchored[i]) continue;
    EXPECT_NEAR(l.rest(2, i), 0, 1e-12);
    ++anchored;
  }
  EXPECT_GT(anchored, 20);
  EXPECT_LT(l.size(), 0.7 * 16 * 10 * 8);
  // The cage the map reads is closed and holds the lattice's volume.
  const GridSurface g = voxel_surface(hybrid_voxels(s));
  models::massspring::TriangleMesh cage{Eigen::Matrix3Xd(3, g.nodes.size()), g.triangles};
  for (std::size_t i = 0; i < g.nodes.size(); ++i) cage.vertices.col(i) = l.rest.col(g.nodes[i]);
  models::massspring::check_closed(cage);
  const models::massspring::Voxels vox = hybrid_voxels(s);
  const double filled = std::count(vox.filled.begin(), vox.filled.end(), 1);
  EXPECT_NEAR(tests::signed_volume(cage.vertices, cage.triangles), filled * std::pow(vox.spacing, 3), 1e-12);
  EXPECT_EQ(h.cage_masses(), g.nodes);
}

// Coming down onto the loaf at points over its top: contact begins where
// the drawn surface is; a 4 mm press is felt inside the friction cone about
// the surface's normal, the drawn surface under the stylus gives way by
// over half the stylus's depth (the cube's is 0.75: what is seen follows
// what is felt as closely), the load taken is the force felt, and the
// surface is back at rest within 0.1 mm 2 s after release.
TEST(HybridShape, AnOrganIsTouchedOnItsDrawnSurfaceAndComesBack) {
  const HybridSpec s = loaf_spec();
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(0.01, -0.02), Eigen::Vector2d(0.02, -0.016)}) {
    Hybrid h(s);
    const double top = height_over(h.visual_rest().vertices, h.triangles(), at);
    double entry = -1;
    for (double z = top + 0.002; z > top - 0.004 && entry < 0; z -= 2e-5)
      if (h.touch(1e-3, Eigen::Vector3d(at.x(), at.y(), z), false).in_contact) entry = z;
    EXPECT_NEAR(entry, top, 5e-5) << "at " << at.transpose();
    Touch t;
    const Eigen::Vector3d above(at.x(), at.y(), top + 0.001);
    for (int k = 0; k < 1500; ++k) {
      t = h.touch(1e-3, above - Eigen::Vector3d(0, 0, 0.005 * std::min(1.0, (k + 1) / 300.0)), false);
      EXPECT_NEAR((t.force + h.tick_load().rowwise().sum()).norm(), 0, 1e-12);
      h.advance();
    }
    ASSERT_TRUE(t.in_contact);
    EXPECT_GT(t.force.z(), 0.05) << "at " << at.transpose();
    EXPECT_GT(t.force.normalized().dot(t.normal), std::cos(std::atan(0.5)) - 0.01) << "at " << at.transpose();
    const double sunk = top - height_over(h.surface(), h.triangles(), at);
    EXPECT_GT(sunk, 0.5 * t.depth) << "the drawn surface gives way under the stylus, at " << at.transpose();
    for (int k = 0; k < 2000; ++k) h.touch(1e-3, above + Eigen::Vector3d(0, 0, 0.01), false), h.advance();
    EXPECT_LT((h.surface() - h.visual_rest().vertices).colwise().norm().maxCoeff(), 1e-4) << "at " << at.transpose();
  }
}

// What is seen follows what is felt all over an organ:
// the loaf with a stiff lobe at +x, as the default scene's organ has,
// pressed from above 4 mm past its drawn surface and held at points along
// it and off its middle, on both sides, at its middle and near its ends.
// Under the force felt, the drawn surface follows the stylus's tip within
// 15 % of the tip's depth at every point: follow() brings the force to
// the one under which the behavior model sinks as deep as the stylus (a
// force gain alone, fitted at rest, leaves the surface short of the tip
// where the organ is thin or stiff). And the force felt along the
// stylus's press is the behavior model's static force for that press
// within 15 %.
TEST(HybridShapeSlow, WhatIsSeenFollowsWhatIsFeltAllOverAnOrgan) {
  HybridSpec s = loaf_spec();
  s.stiff_ratio = 4;
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(-0.015, 0), Eigen::Vector2d(-0.01, 0.006), Eigen::Vector2d(-0.005, 0),
        Eigen::Vector2d(0, -0.006), Eigen::Vector2d(0, 0), Eigen::Vector2d(0.005, 0.006), Eigen::Vector2d(0.01, 0),
        Eigen::Vector2d(0.015, 0)}) {
    Hybrid h(s);
    const Eigen::Vector2d at = s.centre.head<2>() + p;
    const Eigen::Vector3d above(at.x(), at.y(), height_over(h.visual_rest().vertices, h.triangles(), at) + 0.002);
    Touch t;
    for (int k = 0; k < 1500; ++k) {
      t = h.touch(1e-3, above - Eigen::Vector3d(0, 0, 0.006 * std::min(1.0, (k + 1) / 300.0)), false);
      h.advance();
    }
    ASSERT_TRUE(t.in_contact) << "at " << p.transpose();
    // How much of the tip's depth in the object at rest the surface drawn
    // has followed: its depth inside that surface over its depth inside
    // the surface at rest, from one.
    const Eigen::Vector3d tip = above - Eigen::Vector3d(0, 0, 0.006);
    const double seen =
        1 - depth_inside(h.surface(), h.triangles(), tip) / depth_inside(h.visual_rest().vertices, h.triangles(), tip);
    EXPECT_NEAR(seen, 1, 0.15) << "at " << p.transpose() << ": " << t.force.norm() << " N";
    // The force felt along the stylus's press (from the proxy to the HIP)
    // is the behavior model's static force for that press of its drawn
    // surface.
    const Eigen::Vector3d press = tip - h.proxy();
    const double felt = -t.force.dot(press.normalized());
    const double behavior = behavior_surface_force(s, h.proxy(), {press.norm()}, press)[0];
    EXPECT_NEAR(felt / behavior, 1, 0.15)
        << "at " << p.transpose() << ": felt " << felt << " N, behavior " << behavior << " N";
  }
}

// Energy is not created: pressed 5 mm from above and held, with an
// encoder's jitter (5 um every other tick), then let go slowly or in 10
// ms, at points of the loaf on both sides and between, the stylus gets
// back no more work than it did on the object (follow() stiffens a held
// press, and the S-Chain's force lags on the way out). The bound on the
// force does not chatter under the jitter (under 2 % from tick to tick
// while held), and, let go slowly, the force tapers off as the stylus
// comes out rather than dropping when contact ends (at most 5 % of its
// peak at the last tick of contact).
TEST(HybridShapeSlow, APressGivesBackNoMoreWorkThanItTook) {
  HybridSpec s = loaf_spec();
  s.stiff_ratio = 4;
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(-0.01, 0.006), Eigen::Vector2d(0, 0), Eigen::Vector2d(0.01, 0)}) {
    Hybrid h(s);
    const Eigen::Vector2d at = s.centre.head<2>() + p;
    const Eigen::Vector3d above(at.x(), at.y(), height_over(h.visual_rest().vertices, h.triangles(), at) + 0.001);
    for (const int out : {300, 10}) {
      double in_work = 0, out_work = 0, peak = 0, last = 0, chatter = 0;
      Eigen::Vector3d from = above;
      for (int k = 0; k < 300 + 1000 + out + 200; ++k) {
        double d = 0.006;
        if (k < 300)
          d *= (k + 1) / 300.0;
        else if (k < 1300)
          d += 5e-6 * (k % 2);
        else
          d *= std::max(0.0, 1 - (k - 1299.0) / out);
        const Eigen::Vector3d hip = above - Eigen::Vector3d(0, 0, d);
        const Touch t = h.touch(1e-3, hip, false);
        h.advance();
        const double work = -t.force.dot(hip - from);
        (work > 0 ? in_work : out_work) += work;
        if (k >= 1100 && k < 1300) chatter = std::max(chatter, std::abs(t.force.norm() - last) / last);
        if (t.in_contact) last = t.force.norm(), peak = std::max(peak, last);
        from = hip;
      }
      EXPECT_LE(-out_work, in_work * (1 + 1e-9)) << "at " << p.transpose() << ", out in " << out << " ms";
      EXPECT_GT(-out_work, 0.5 * in_work) << "at " << p.transpose() << ", out in " << out << " ms";
      EXPECT_LT(chatter, 0.02) << "at " << p.transpose();
      if (out == 300) {
        EXPECT_LT(last, 0.05 * peak) << "at " << p.transpose() << ": " << last << " of " << peak << " N";
      }
    }
  }
}

// Press 3 mm on top, then slide 10 mm sideways at 1 cm/s, on each side:
// past its onset the force leans off the normal by no more than the
// coefficient + 0.02, and by at least 0.8 of it; with a static coefficient
// above the dynamic one, no more than the static one (the chains' force is
// not linear in the offset, so a slip can end inside the dynamic cone and
// stick again: stick-slip, as a real stroke may).
TEST(HybridSlow, AStrokeFeelsItsFrictionAndNoMore) {
  for (const haptic::Friction f : {haptic::Friction{0.3, 0.3}, haptic::Friction{0, 0}, haptic::Friction{0.5, 0.3}})
    for (const double side : {-1.0, 1.0}) {
      HybridSpec s = quick();
      s.friction = f;
      s.stiff_ratio = 4;
      Hybrid h(s);
      const Eigen::Vector3d start = s.centre + Eigen::Vector3d(side * 0.02 - 0.005, 0.0013, 0.5 * s.size);
      for (int k = 0; k <= 400; ++k) {
        h.touch(1e-3, start + Eigen::Vector3d(0, 0, 0.001 - 0.004 * std::min(1.0, k / 300.0)), false);
        h.advance();
      }
      double most = 0, sum = 0;
      int ticks = 0;
      for (int k = 1; k <= 1000; ++k) {
        const Touch t = h.touch(1e-3, start + Eigen::Vector3d(1e-5 * k, 0, -0.003), false);
        h.advance();
        ASSERT_TRUE(t.in_contact) << k;
        if (k < 300) continue;  // the stroke's onset, before it slips
        const double push = t.force.dot(t.normal), r = (t.force - push * t.normal).norm() / push;
        most = std::max(most, r), sum += r, ++ticks;
      }
      EXPECT_LE(most, f.static_mu + 0.02) << "mu " << f.static_mu << " side " << side;
      EXPECT_GE(sum / ticks, 0.8 * f.dynamic_mu) << "mu " << f.dynamic_mu << " side " << side;
    }
}

// Frictionless, entering the top face between chain nodes: the force is
// along the drawn surface's normal.
TEST(Hybrid, EnteringBetweenNodesIsFeltAlongTheNormal) {
  HybridSpec s = quick();
  s.friction = {0, 0};
  Hybrid h(s);
  const Eigen::Vector3d above = s.centre + Eigen::Vector3d(0.0037, -0.0041, 0.5 * s.size + 0.001);
  double worst = 0;
  for (int k = 0; k <= 300; ++k) {
    const Touch t = h.touch(1e-3, above - Eigen::Vector3d(0, 0, 0.004 * std::min(1.0, k / 200.0)), false);
    h.advance();
    if (t.in_contact && !t.force.isZero()) worst = std::max(worst, std::acos(std::min(1.0, t.force.normalized().z())));
  }
  EXPECT_LT(worst * 180 / M_PI, 5);
}

// Every tick the behavior model takes the opposite of the force felt;
// the first tick of contact is no harder than the stiffest chain times its
// motion; a press held on the organ's stiff side is steady (spread under
// 2 % over 0.5 s).
TEST(HybridSlow, TheForceFeltIsTheLoadTakenStartsWithoutAKickAndHoldsSteady) {
  const HybridSpec s = organ();
  Hybrid h(s);
  const Eigen::Vector3d above = s.centre + Eigen::Vector3d(0.006, 0.002, 0.5 * s.size + 0.002);
  Eigen::Vector3d last = above;
  int touched = 0;
  double first = 0;  // N/m: the force over the tick's step at the first contact
  double sum = 0, square = 0;
  for (int k = 0; k <= 1500; ++k) {
    const Eigen::Vector3d hip = above - Eigen::Vector3d(0, 0, std::min(0.006, 4e-5 * k));
    const Touch t = h.touch(1e-3, hip, false);
    const Eigen::Vector3d taken = h.tick_load().rowwise().sum();
    EXPECT_LE((taken + t.force).norm(), 1e-12 * (1 + t.force.norm())) << "tick " << k;
    // No kick: the first contact's force over its step is no stiffer than
    // the press is ten ticks on.
    if (t.in_contact && touched == 0) first = t.force.norm() / (hip - last).norm();
    if (t.in_contact && touched == 10) {
      EXPECT_LE(first, 1.5 * t.stiffness) << "first " << first << " N/m";
    }
    touched += t.in_contact;
    if (k > 1000) sum += t.force.norm(), square += t.force.squaredNorm();
    last = hip;
    h.advance();
  }
  EXPECT_GT(touched, 10);
  const double mean = sum / 500, spread = std::sqrt(std::max(0.0, square / 500 - mean * mean));
  EXPECT_GT(mean, 0.05);
  EXPECT_LT(spread, 0.02 * mean);
}

// A device's encoder moves the HIP in steps (the Omni's 0.055 mm): the
// organ's stiff side pressed at 2.75 cm/s in a step every other tick stays
// touched from its first tick and its force never falls between ticks.
TEST(HybridSlow, AStepwiseHipPressesWithoutChatter) {
  const HybridSpec s = organ();
  Hybrid h(s);
  const Eigen::Vector3d above = s.centre + Eigen::Vector3d(0.006, 0.002, 0.5 * s.size + 0.002);
  int touched = 0;
  double last = 0, worst = 1;
  for (int k = 0; k <= 400; ++k) {
    const Touch t = h.touch(1e-3, above - Eigen::Vector3d(0, 0, 0.055e-3 * std::min(k / 2, 100)), false);
    h.advance();
    if (touched > 0) {
      ASSERT_TRUE(t.in_contact) << k;
    }
    if (t.in_contact) ++touched;
    if (touched > 20) worst = std::min(worst, t.force.norm() / last);
    last = t.force.norm();
  }
  EXPECT_GT(touched, 250);  // from about tick 120: the ellipsoid is 1.3 mm below the cage's top there
  EXPECT_GT(worst, 0.95);
}

// Pushed in one tick from above the top to the cube's centre, then held
// there for a simulated minute.
TEST(HybridSlow, MinuteLongContactAtTheCentreStaysFinite) {
  const HybridSpec s = quick();
  Hybrid h(s);
  h.touch(1e-3, s.centre + Eigen::Vector3d(0.001, 0.002, 0.6 * s.size), false);
  Touch t;
  for (int k = 0; k < 60000; ++k) {
    t = h.touch(1e-3, s.centre, false);
    if (k % 10 == 0) h.advance();
  }
  EXPECT_TRUE(t.in_contact);
  EXPECT_TRUE(t.force.allFinite());
  EXPECT_GT(t.force.norm(), 0);
  const Eigen::Matrix3Xd x = h.surface();
  EXPECT_TRUE(x.allFinite());
  EXPECT_EQ(x.cols(), 5402);
  EXPECT_TRUE(h.state().x.allFinite());
}

}  // namespace
}  // namespace hcosim::models::deformable
