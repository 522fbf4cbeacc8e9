// Forces from many sources: each source's local model summed at the
// position, silent sources dropped, a late source covered by its latest model.
#include <gtest/gtest.h>

#include "models/haptic/force_sum.h"
#include "models/haptic/local_model.h"

namespace hcosim::models::haptic {
namespace {

LocalModel constant(const Eigen::Vector3d& f) {
  LocalModel m;
  m.force = f;
  return m;
}

TEST(HapticForceSum, SumsFreshSourcesAndDropsSilentOnes) {
  ForceSum sum(0.05);
  const Eigen::Vector3d x(0.3, 0.2, 0.1);  // a constant model is the same everywhere
  sum.set("liver", constant({0, 0, 1}), 0.0);
  sum.set("cube", constant({1, 0, 0}), 0.01);
  sum.set("liver", constant({0, 0, 2}), 0.02);  // replaces, does not add
  EXPECT_EQ(sum.total(0.03, x), Eigen::Vector3d(1, 0, 2));
  EXPECT_EQ(sum.sources(), 2u);
  EXPECT_EQ(sum.force_of("cube"), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(sum.total(0.065, x), Eigen::Vector3d(0, 0, 2));  // cube silent for 55 ms
  EXPECT_EQ(sum.expired(), 1u);
  EXPECT_FALSE(sum.has("cube"));
  EXPECT_EQ(sum.force_of("cube"), Eigen::Vector3d::Zero());
  EXPECT_EQ(sum.total(0.2, x), Eigen::Vector3d::Zero());
  EXPECT_EQ(sum.sources(), 0u);
  EXPECT_THROW(ForceSum(0), std::invalid_argument);
}

TEST(HapticForceSum, EvaluatesEachSourceAtThePosition) {
  ForceSum sum(0.05);
  // A wall at z = 0, 500 N/m, answered with the HIP 2 mm inside.
  sum.set("wall", contact_model({0, 0, 1.0}, {0, 0, -0.002}, {0, 0, 1}, 500, 0.005), 0);
  EXPECT_NEAR(sum.total(0.001, {0.001, 0, -0.003}).z(), 1.5, 1e-12);
  EXPECT_NEAR(sum.force_of("wall").z(), 1.5, 1e-12);
}

TEST(HapticForceSum, CoversASourceByItsLatestModel) {
  ForceSum sum(0.05);
  LocalModel free;
  free.radius = 0.02;
  sum.set("ball", free, 0.0);
  EXPECT_TRUE(sum.covers("ball", {0.01, 0, 0}));
  EXPECT_FALSE(sum.covers("ball", {0.03, 0, 0}));
  EXPECT_FALSE(sum.covers("cube", {0, 0, 0}));  // never answered
  sum.set("ball", contact_model({0, 0, 1}, {0, 0, 0}, {0, 0, 1}, 500, 0.002), 0.001);
  EXPECT_FALSE(sum.covers("ball", {0, 0, 0}));
}

}  // namespace
}  // namespace hcosim::models::haptic
