#include <gtest/gtest.h>

#include "device/haptic_idl.h"
#include "validate.h"

namespace hcosim::device {
namespace {

TEST(HapticIdl, ForceCarriesTheFeel) {
  Feel feel;
  feel.force = {0, 0, 1.5};
  feel.in_contact = true;
  feel.depth = 0.003;
  feel.stiffness = 500;
  StepStamp stamp;
  stamp.step(7);
  const ForceFeedback f = force_feedback("rigid", "omni", 42, stamp, feel);
  EXPECT_EQ(f.source().to_string(), "rigid");
  EXPECT_EQ(f.device().to_string(), "omni");
  EXPECT_EQ(f.answers_seq(), 42u);
  EXPECT_EQ(f.stamp().step(), 7u);
  EXPECT_DOUBLE_EQ(f.force().z(), 1.5);
  EXPECT_TRUE(f.in_contact());
  EXPECT_DOUBLE_EQ(f.penetration_m(), 0.003);
  EXPECT_DOUBLE_EQ(f.stiffness_n_per_m(), 500);
  EXPECT_FALSE(validate(f));
}

TEST(HapticIdl, AnswerCarriesItsLocalModel) {
  const Feel feel = contact_feel({0, 0, 1}, {0.01, 0, -0.002}, {0, 0, 1}, 500, 0.002, 0.003);
  const ForceFeedback f = force_feedback("wall", "omni", 3, StepStamp{}, feel);
  EXPECT_FALSE(validate(f));
  const haptic::LocalModel m = local_model(f);
  EXPECT_EQ(m.force, feel.force);
  EXPECT_EQ(m.position, feel.position);
  EXPECT_EQ(m.jacobian, feel.jacobian);
  EXPECT_EQ(m.jacobian(2, 2), -500);
  EXPECT_EQ(m.normal, feel.normal);
  EXPECT_EQ(m.radius, 0.003);
  EXPECT_NEAR(haptic::evaluate(m, {0.01, 0, -0.003}).z(), 1.5, 1e-12);
}

TEST(HapticIdl, VectorsRoundTrip) {
  const Eigen::Vector3d v(0.1, -2, 3e-5);
  EXPECT_EQ(from_idl(to_idl(v)), v);
}

}  // namespace
}  // namespace hcosim::device
