// The MuJoCo cross-check's scenarios agree within their tolerances.
#include <cmath>

#include <gtest/gtest.h>

#include "models/rigid/crosscheck.h"

namespace hcosim::models::rigid {
namespace {

// Every scenario agrees with MuJoCo within its stated tolerance, and MuJoCo
// conserves momentum too where no outside force acts.
TEST(RigidMujoco, ScenariosAgreeWithinTheirTolerance) {
  for (const Scenario& s : scenarios()) {
    const Divergence d = crosscheck(s);
    SCOPED_TRACE(s.name);
    EXPECT_LT(d.rel_vel_err, s.tolerance);
    EXPECT_LT(d.rel_angvel_err, s.tolerance);
    EXPECT_LT(d.momentum_drift[0], 1e-12);
    if (s.spec.gravity.isZero()) {
      EXPECT_LT(d.momentum_drift[1], 1e-12);
    }
    if (s.spec.tip.restitution == 1) {
      EXPECT_LT(std::abs(d.energy_change[1]), 0.01);
    }
  }
}

}  // namespace
}  // namespace hcosim::models::rigid
