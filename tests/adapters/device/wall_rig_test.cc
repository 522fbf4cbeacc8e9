// The closed loop against a virtual wall: the simulated hand presses the
// stylus to the depth the force balance predicts, and with forces arriving
// 0 to 5 ms late the passivity controller keeps a wall up to the Omni's
// maximum stiffness stable; without it the same wall buzzes.
#include <gtest/gtest.h>

#include "adapters/device/wall_rig.h"
#include "models/haptic/passivity.h"

namespace hcosim::adapters::device {

// The haptic models this adapter converts.
using namespace models::haptic;
namespace {

TEST(HapticWall, PressReachesTheForceBalanceDepth) {
  for (const double k : {200.0, 500.0, 1000.0}) {
    WallRig rig;
    rig.wall.stiffness = k;
    const WallRun run = run_wall(rig);
    SCOPED_TRACE("k " + std::to_string(k));
    // Within 2 encoder steps of the balance between hand and wall.
    EXPECT_NEAR(run.depth_m, balance_depth(rig), 2 * rig.spec.resolution);
    EXPECT_TRUE(run.stable);
  }
}

TEST(HapticWall, DelayedStiffWallStaysStableWithPassivityControl) {
  for (const double k : {500.0, 1000.0})
    for (const double delay : {0.0, 1e-3, 2e-3, 3e-3, 5e-3}) {
      WallRig rig;
      rig.wall.stiffness = k;
      rig.delay_s = delay;
      const WallRun run = run_wall(rig);
      SCOPED_TRACE("k " + std::to_string(k) + " delay " + std::to_string(delay));
      EXPECT_TRUE(run.stable) << "excursion " << run.peak_to_peak_m << " m, energy out " << run.max_energy_out_j
                              << " J";
      EXPECT_LE(run.max_force_n, rig.spec.max_force);
      EXPECT_LT(run.max_energy_out_j, 1e-3);
      EXPECT_LT(run.peak_to_peak_m, 4 * rig.spec.resolution);
      // The controller only takes energy out: the tip still rests near balance.
      EXPECT_NEAR(run.depth_m, balance_depth(rig), 0.1 * balance_depth(rig));
    }
}

TEST(HapticWall, WithoutPassivityControlTheDelayedWallBuzzes) {
  WallRig rig;
  rig.wall.stiffness = 1000;
  rig.delay_s = 5e-3;
  rig.passivity = false;
  const WallRun run = run_wall(rig);
  EXPECT_FALSE(run.stable);
  EXPECT_GT(run.peak_to_peak_m, 1e-3);
  EXPECT_GT(run.max_energy_out_j, 0.01);
  EXPECT_GT(run.saturated, 0u);
}

TEST(HapticWall, ControllerDampsOnlyAnEnergyDeficit) {
  models::haptic::PassivityController pc(1e-3, 20, 1e-4);
  const Eigen::Vector3d v(0, 0, -0.1);  // moving into a wall that pushes back: it absorbs
  EXPECT_EQ(pc.filter({0, 0, 1}, v, Eigen::Vector3d::Zero()), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(pc.damping(), 0);
  // Pushing the tip along its motion generates energy; past the 1e-4 J
  // banked, it is damped back to zero.
  const Eigen::Vector3d out = pc.filter({0, 0, -2}, v, {0, 0, 1});
  EXPECT_GT(pc.damping(), 0);
  EXPECT_GT(out.z(), -2);
  EXPECT_NEAR(pc.observed_energy() - out.dot(v) * 1e-3, 0, 1e-15);
  EXPECT_THROW(models::haptic::PassivityController(0, 1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::adapters::device
