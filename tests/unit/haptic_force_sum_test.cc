// Forces from many sources: summed while fresh, dropped after the timeout.
#include <gtest/gtest.h>

#include "haptic/force_sum.h"

namespace hcosim::haptic {
namespace {

TEST(HapticForceSum, SumsFreshSourcesAndDropsSilentOnes) {
  ForceSum sum(0.05);
  sum.set("liver", {0, 0, 1}, 0.0);
  sum.set("cube", {1, 0, 0}, 0.01);
  sum.set("liver", {0, 0, 2}, 0.02);  // replaces, does not add
  EXPECT_EQ(sum.total(0.03), Eigen::Vector3d(1, 0, 2));
  EXPECT_EQ(sum.sources(), 2u);
  EXPECT_EQ(sum.total(0.065), Eigen::Vector3d(0, 0, 2));  // cube silent for 55 ms
  EXPECT_EQ(sum.expired(), 1u);
  EXPECT_EQ(sum.total(0.2), Eigen::Vector3d::Zero());
  EXPECT_EQ(sum.sources(), 0u);
  EXPECT_THROW(ForceSum(0), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::haptic
