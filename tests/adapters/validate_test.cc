#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "adapters/validate.h"

namespace hcosim::adapters {
namespace {

HapticState good_state() {
  HapticState s;
  s.device("omni");
  s.orientation().w(1.0);
  s.position().x(0.02);
  return s;
}

TEST(Validate, AdmitsAGoodHapticState) { EXPECT_FALSE(validate(good_state())); }

TEST(Validate, NamesTheNaNField) {
  HapticState s = good_state();
  s.velocity().y(std::nan(""));
  const auto p = validate(s);
  ASSERT_TRUE(p);
  EXPECT_EQ(*p, "velocity.y is NaN");
}

TEST(Validate, RefusesInfAndAbsurdPositions) {
  HapticState s = good_state();
  s.position().z(std::numeric_limits<double>::infinity());
  EXPECT_EQ(validate(s).value_or(""), "position.z is +Inf");
  s.position().z(1e6);
  EXPECT_EQ(validate(s).value_or(""), "position.z = 1e+06 exceeds 10");
}

TEST(Validate, RefusesANonUnitQuaternion) {
  HapticState s = good_state();
  s.orientation().w(0.0);
  EXPECT_TRUE(validate(s));
}

TEST(Validate, ForceFeedbackBounds) {
  ForceFeedback f;
  f.force().x(3.0);
  EXPECT_FALSE(validate(f));
  f.force().x(kMaxForceN * 2);
  EXPECT_TRUE(validate(f));
  f.force().x(1.0);
  f.penetration_m(-0.001);
  EXPECT_EQ(validate(f).value_or(""), "penetration_m is negative");
}

// A device evaluates an answer's local model every late tick: a NaN there
// would reach the stylus as surely as a NaN force.
TEST(Validate, ForceFeedbackLocalModel) {
  ForceFeedback f;
  f.normal().z(1.0);
  f.jacobian()[8] = -500;
  f.valid_radius_m(0.002);
  EXPECT_FALSE(validate(f));
  f.jacobian()[4] = std::nan("");
  EXPECT_EQ(validate(f).value_or(""), "jacobian[4] is NaN");
  f.jacobian()[4] = 0;
  f.normal().z(0.5);
  EXPECT_EQ(validate(f).value_or("").rfind("normal is neither zero nor a unit vector", 0), 0u);
  f.normal().z(0);
  f.valid_radius_m(-1);
  EXPECT_EQ(validate(f).value_or(""), "valid_radius_m is negative");
  f.valid_radius_m(0);
  f.position().y(std::numeric_limits<double>::infinity());
  EXPECT_EQ(validate(f).value_or(""), "position.y is +Inf");
}

TEST(Validate, MeshSizesMustAgree) {
  DeformedMesh m;
  m.positions() = {0, 0, 0, 1, 1, 1};
  EXPECT_FALSE(validate(m));
  m.normals() = {0, 0, 1};
  EXPECT_EQ(validate(m).value_or(""), "normals and positions differ in length");
  m.normals().clear();
  m.positions().push_back(2);
  EXPECT_TRUE(validate(m));
  m.positions() = {0, std::nanf(""), 0};
  EXPECT_EQ(validate(m).value_or(""), "positions[1] = NaN");
}

TEST(Validate, TopologyIndicesStayInRange) {
  MeshTopology t;
  t.vertex_count(3);
  t.triangles() = {0, 1, 2};
  EXPECT_FALSE(validate(t));
  t.triangles() = {0, 1, 3};
  EXPECT_EQ(validate(t).value_or(""), "triangles[2] = 3 is not below vertex_count 3");
}

TEST(Validate, CameraFrameSizeMatchesEncoding) {
  CameraFrame f;
  f.width(4);
  f.height(2);
  f.encoding("bgr8");
  f.fx(1), f.fy(1);
  f.data().assign(24, 0);
  EXPECT_FALSE(validate(f));
  f.encoding("mono8");
  EXPECT_TRUE(validate(f));
  f.encoding("rgb16");
  EXPECT_EQ(validate(f).value_or(""), "encoding 'rgb16' is not bgr8 or mono8");
}

TEST(Validate, RigidStateNeedsAUnitQuaternionAndFiniteVelocities) {
  RigidBodyState s;
  s.pose().orientation().w(1.0);
  EXPECT_FALSE(validate(s));
  s.angular_velocity().z(std::numeric_limits<double>::infinity());
  ASSERT_TRUE(validate(s));
  EXPECT_EQ(*validate(s), "angular_velocity.z is +Inf");
}

TEST(Validate, DivergencesAreNorms) {
  RigidDivergence d;
  d.position_m(0.01);
  EXPECT_FALSE(validate(d));
  d.velocity_m_s(-1);
  ASSERT_TRUE(validate(d));
  EXPECT_EQ(*validate(d), "a divergence is -1, not a norm");
  d.velocity_m_s(std::nan(""));
  EXPECT_EQ(*validate(d), "a divergence is NaN, not a norm");
}

TEST(Validate, ClockTickNeedsAPositiveStep) {
  ClockTick t;
  EXPECT_TRUE(validate(t));
  t.step_ns(1'000'000);
  EXPECT_FALSE(validate(t));
}

}  // namespace
}  // namespace hcosim::adapters
