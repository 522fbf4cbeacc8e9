// The behavior model's static answers to a press and the force gain made
// of them: the power law between the gain's samples, the gain's forces as
// the behavior model's own settled presses at its gain points, one gain
// per key, the volume floors against snap-through, and presses along a
// direction.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "models/deformable/force_gain.h"
#include "models/deformable/hybrid_build.h"

namespace hcosim::models::deformable {
namespace {

// Tests that do not concern the visual map use the one that costs nothing to build.
HybridSpec trilinear_cube() {
  HybridSpec s;
  s.map = VisualMap::trilinear;
  return s;
}

// The top-face mass above the centre.
int top_centre(const HybridSpec& s) {
  const int n = s.elements;
  return n / 2 + n * (n / 2 + n * (n - 1));
}

TEST(ForceGain, APowerLawRunsBetweenTheSamples) {
  const std::vector<double> xs{1, 2, 4};
  const std::vector<double> ys{1, 4, 16};  // x^2
  for (const double x : {1.0, 1.5, 2.0, 3.0, 4.0, 6.0}) EXPECT_NEAR(power_law(xs, ys.data(), x), x * x, 1e-12) << x;
  EXPECT_NEAR(power_law(xs, ys.data(), 0.5), 0.5, 1e-12);  // proportional below the first
  const std::vector<double> flat{1, 0, 16};
  EXPECT_EQ(power_law(xs, flat.data(), 1.5), 0);
  ForceGain g;
  g.depth = xs, g.soft = ys, g.stiff = {2, 8, 32};
  EXPECT_NEAR(g.at(3, false), 9, 1e-12);
  EXPECT_NEAR(g.at(3, true), 18, 1e-12);
  g.stiff.clear();
  EXPECT_NEAR(g.at(3, true), 9, 1e-12);
}

// A small cube's gain: at each side's gain point its forces are the
// behavior model's settled press of its drawn surface there, growing with
// depth, the stiff side's harder; its compliance at rest is positive at
// every visual vertex off the floor. A spec of the same key gets the same gain once per
// process.
TEST(ForceGain, ItsForcesAreTheSettledPressesAtTheGainPoints) {
  HybridSpec s = trilinear_cube();
  s.elements = 5;
  s.stiff_ratio = 4;
  const ForceGain g = force_gain(s);
  ASSERT_EQ(g.depth.size(), 21u);
  EXPECT_NEAR(g.depth.back(), 0.25 * s.size, 1e-12);
  ASSERT_EQ(g.soft.size(), 21u);
  ASSERT_EQ(g.stiff.size(), 21u);
  for (std::size_t j = 1; j < g.depth.size(); ++j) {
    EXPECT_GT(g.soft[j], g.soft[j - 1]) << j;
    EXPECT_GT(g.stiff[j], g.soft[j]) << j;
  }
  const SChain chains(hybrid_chains(s), s.relax_rate, s.limit_stiffness);
  for (const bool stiff : {false, true}) {
    const Eigen::Vector3d at = find_gain_point(s, hybrid_voxels(s), chains, stiff).first;
    const std::vector<double> press = behavior_surface_force(s, at, {g.depth[4], g.depth[12]});
    const std::vector<double>& f = stiff ? g.stiff : g.soft;
    EXPECT_NEAR(press[0] / f[4], 1, 0.02) << (stiff ? "stiff" : "soft");
    EXPECT_NEAR(press[1] / f[12], 1, 0.02) << (stiff ? "stiff" : "soft");
  }
  // Every visual vertex's but the floor's, which is anchored.
  const models::massspring::TriangleMesh visual = hybrid_visual(s);
  ASSERT_EQ(g.compliance.size(), std::size_t(visual.vertices.cols()));
  const double floor = rest_box(s).min().z();
  for (int v = 0; v < visual.vertices.cols(); ++v) {
    if (visual.vertices(2, v) > floor + 1e-9) {
      ASSERT_GT(g.compliance[v], 0) << "vertex " << v;
    }
  }
  EXPECT_GT(g.soft_compliance, g.stiff_compliance);

  HybridSpec moved = s;
  moved.centre.x() += 0.3;
  const ForceGain first = shared_force_gain(s, {}), again = shared_force_gain(moved, {});
  EXPECT_EQ(first.soft, g.soft);
  EXPECT_EQ(again.soft, first.soft);
  EXPECT_EQ(again.compliance, first.compliance);
}

// Pressed at the top's centre past one lattice spacing (11 mm), the
// behavior model's static force keeps rising: the volume floors keep the
// pressed mass from punching through the layer below. Without them
// (volume 0) it dropped from 0.68 N at 12 mm to 0.48 N at 14 mm, where the
// floors give 0.89 and 1.13 N. They leave the springs alone below the
// floor: at 4 mm both give the same force.
TEST(ForceGainSlow, TheBehaviorModelDoesNotSnapThroughPastOneCell) {
  HybridSpec s = trilinear_cube();
  const Eigen::Vector3d down(0, 0, -1);
  double last = 0;
  for (const double depth : {0.004, 0.01, 0.012, 0.014, 0.016, 0.02}) {
    const double f = behavior_static_force(s, top_centre(s), depth * down).z();
    EXPECT_GT(f, last) << "depth " << depth;
    last = f;
  }
  const double floors_4mm = behavior_static_force(s, top_centre(s), 0.004 * down).z();
  s.volume = 0;
  EXPECT_NEAR(behavior_static_force(s, top_centre(s), 0.004 * down).z(), floors_4mm, 1e-9);
  EXPECT_LT(behavior_static_force(s, top_centre(s), 0.014 * down).z(),
            behavior_static_force(s, top_centre(s), 0.012 * down).z());
}

// The behavior model's force for a press of its drawn surface along a
// direction is its force for a press along the normal where that
// direction is the inward normal, and differs from it along another.
TEST(ForceGainSlow, ASurfacePressAlongTheNormalIsTheNormalPress) {
  const HybridSpec s = trilinear_cube();
  const SChain chains(hybrid_chains(s), s.relax_rate, s.limit_stiffness);
  const Eigen::Vector3d at = find_gain_point(s, hybrid_voxels(s), chains, false).first, down(0, 0, -1),
                        slant = Eigen::Vector3d(1, 0, -2).normalized();
  const std::vector<double> normal = behavior_surface_force(s, at, {0.001, 0.004});
  const std::vector<double> along = behavior_surface_force(s, at, {0.001, 0.004}, down);
  // Not bit for bit: the normal press starts its search from the
  // compliance along the face's vertex normals, which lean a little, and
  // the search ends within 1 % of the depth (1.5e-5 apart here).
  for (int j = 0; j < 2; ++j) EXPECT_NEAR(along[j] / normal[j], 1, 1e-3) << "depth " << j;
  // 0.81 here, 27 degrees off the normal: the lattice is softer slanted.
  EXPECT_LT(behavior_surface_force(s, at, {0.004}, slant)[0] / normal[1], 0.95);
  EXPECT_THROW(behavior_surface_force(s, at, {0.001}, Eigen::Vector3d(NAN, 0, -1)), std::invalid_argument);
  EXPECT_THROW(behavior_surface_force(s, at, {0.002, 0.001}), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::deformable
