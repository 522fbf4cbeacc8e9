// A source's local force model: a linear contact reproduced inside its
// radius, let go when the contact opens, held at the radius, free space
// covered only inside its radius, bad arguments refused.
#include <gtest/gtest.h>

#include "models/haptic/local_model.h"

namespace hcosim::models::haptic {
namespace {

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

}  // namespace
}  // namespace hcosim::models::haptic
