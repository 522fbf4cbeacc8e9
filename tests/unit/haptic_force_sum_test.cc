// Forces from many sources: each source's local model summed at the
// device's position while fresh, dropped after the timeout; the local
// model itself against the contact it linearizes.
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

// A penalty wall at z = 0 of stiffness k: the reference the model must
// reproduce wherever it is valid, since the wall is linear.
TEST(HapticLocalModel, ReproducesALinearContactInsideItsRadius) {
  const double k = 800;
  const auto wall = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(0, 0, k * std::max(0.0, -x.z())); };
  const Eigen::Vector3d p(0.01, -0.02, -0.001);
  const LocalModel m = contact_model(wall(p), p, {0, 0, 1}, k, 0.004);
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(0, 0, -0.001), Eigen::Vector3d(0.002, -0.001, 0.0005),
                                   Eigen::Vector3d(0.001, 0.001, -0.002), Eigen::Vector3d(0, 0, 0)})
    EXPECT_NEAR((evaluate(m, p + d) - wall(p + d)).norm(), 0, 1e-12) << d.transpose();
  // Sliding along the wall changes nothing: no stiffness across the normal.
  EXPECT_NEAR((evaluate(m, p + Eigen::Vector3d(0.003, 0.002, 0)) - wall(p)).norm(), 0, 1e-12);
}

TEST(HapticLocalModel, LetsGoWhenTheContactOpens) {
  const Eigen::Vector3d p(0, 0, -0.001);
  const LocalModel m = contact_model({0, 0, 0.5}, p, {0, 0, 1}, 500, 0.005);
  EXPECT_EQ(evaluate(m, {0, 0, 0.0005}), Eigen::Vector3d::Zero());  // out of the wall: no pull
  // Without a normal (a grab), the same offset pulls.
  LocalModel grab = m;
  grab.normal.setZero();
  EXPECT_NEAR(evaluate(grab, {0, 0, 0.0005}).z(), -0.25, 1e-12);
}

TEST(HapticLocalModel, HoldsItsExpansionAtTheRadius) {
  const LocalModel m = contact_model({0, 0, 1}, {0, 0, -0.002}, {0, 0, 1}, 500, 0.001);
  // 3 mm deeper, but the expansion is trusted for 1 mm only.
  EXPECT_NEAR(evaluate(m, {0, 0, -0.005}).z(), 1.5, 1e-12);
  LocalModel held = m;
  held.radius = 0;
  EXPECT_EQ(evaluate(held, {0, 0, -0.005}), Eigen::Vector3d(0, 0, 1));
}

TEST(HapticLocalModel, RefusesBadArguments) {
  LocalModel m;
  EXPECT_THROW(evaluate(m, {std::nan(""), 0, 0}), std::invalid_argument);
  m.radius = -1;
  EXPECT_THROW(evaluate(m, {0, 0, 0}), std::invalid_argument);
}

// A free-space model covers only inside its radius, and only a model that
// is exactly zero there: any force or stiffness needs its source's answer.
TEST(HapticLocalModel, CoversFreeSpaceOnlyInsideItsRadius) {
  LocalModel free;
  free.position = {0.1, 0, 0};
  free.radius = 0.01;
  EXPECT_TRUE(covers(free, {0.105, 0, 0}));
  EXPECT_FALSE(covers(free, {0.111, 0, 0}));
  LocalModel none = free;
  none.radius = 0;  // no contact, but no free space vouched for either
  EXPECT_FALSE(covers(none, free.position));
  LocalModel pushing = free;
  pushing.force = {0, 0, 1e-9};
  EXPECT_FALSE(covers(pushing, free.position));
  LocalModel stiff = free;
  stiff.jacobian(2, 2) = -100;
  EXPECT_FALSE(covers(stiff, free.position));
  EXPECT_EQ(evaluate(free, {0.105, 0, 0}), Eigen::Vector3d::Zero());
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
