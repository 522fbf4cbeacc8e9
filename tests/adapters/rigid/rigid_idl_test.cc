#include <cmath>

#include <gtest/gtest.h>

#include "adapters/rigid/rigid_idl.h"
#include "adapters/validate.h"

namespace hcosim::adapters::rigid {

// The rigid models this adapter converts.
using namespace models::rigid;
namespace {

Body spinning_cube() {
  Body b;
  b.shape = Shape::cube;
  b.x = {0.1, -0.2, 0.03};
  b.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  b.v = {0.5, 0, 0};
  b.w = {0, 0, 4};
  return b;
}

TEST(RigidIdl, StateCarriesPoseVelocitiesAndBackend) {
  const RigidBodyState s = body_state("box", StepStamp(), spinning_cube(), "mujoco");
  EXPECT_EQ(s.body().to_string(), "box");
  EXPECT_EQ(s.shape().to_string(), "cube");
  EXPECT_EQ(s.backend().to_string(), "mujoco");
  EXPECT_DOUBLE_EQ(s.pose().position().y(), -0.2);
  EXPECT_NEAR(s.pose().orientation().w(), std::cos(0.15), 1e-15);
  EXPECT_NEAR(s.pose().orientation().z(), std::sin(0.15), 1e-15);
  EXPECT_DOUBLE_EQ(s.linear_velocity().x(), 0.5);
  EXPECT_DOUBLE_EQ(s.angular_velocity().z(), 4);
  EXPECT_FALSE(validate(s));
}

TEST(RigidIdl, DivergenceIsTheNormOfEachDifference) {
  const Body a = spinning_cube();
  models::rigid::Body m = a;
  m.x.z() += 0.003;
  m.v.y() = -0.4;
  m.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 + 0.5, Eigen::Vector3d::UnitZ()));
  const RigidDivergence d = divergence("box", StepStamp(), a, m);
  EXPECT_NEAR(d.position_m(), 0.003, 1e-15);
  EXPECT_NEAR(d.velocity_m_s(), 0.4, 1e-15);
  EXPECT_NEAR(d.orientation_rad(), 0.5, 1e-7);
  EXPECT_DOUBLE_EQ(d.angular_velocity_rad_s(), 0);
  EXPECT_FALSE(validate(d));
}

TEST(RigidIdl, OppositeQuaternionsAreOneOrientation) {
  const Body a = spinning_cube();
  models::rigid::Body m = a;
  m.q.coeffs() = -a.q.coeffs();
  EXPECT_EQ(divergence("box", StepStamp(), a, m).orientation_rad(), 0);
}

}  // namespace
}  // namespace hcosim::adapters::rigid
