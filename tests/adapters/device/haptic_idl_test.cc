#include <gtest/gtest.h>

#include "adapters/device/haptic_idl.h"
#include "adapters/validate.h"

namespace hcosim::adapters::device {

// The haptic models this adapter converts.
using namespace models::haptic;
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
  const models::haptic::LocalModel m = local_model(f);
  EXPECT_EQ(m.force, feel.force);
  EXPECT_EQ(m.position, feel.position);
  EXPECT_EQ(m.jacobian, feel.jacobian);
  EXPECT_EQ(m.jacobian(2, 2), -500);
  EXPECT_EQ(m.normal, feel.normal);
  EXPECT_EQ(m.radius, 0.003);
  EXPECT_NEAR(models::haptic::evaluate(m, {0.01, 0, -0.003}).z(), 1.5, 1e-12);
}

TEST(HapticIdl, VectorsRoundTrip) {
  const Eigen::Vector3d v(0.1, -2, 3e-5);
  EXPECT_EQ(from_idl(to_idl(v)), v);
}

// A free-space answer carries no force and the clearance as its radius, and
// lets a source skip states while it still covers the HIP, for half the
// horizon at most; a contact never lets it skip.
TEST(HapticIdl, FreeSpaceAnswersCoverTheHipForHalfTheHorizon) {
  const Eigen::Vector3d hip(0.01, 0.02, 0.03);
  const Feel f = free_feel(hip, 0.004);
  EXPECT_FALSE(f.in_contact);
  EXPECT_EQ(f.force, Eigen::Vector3d::Zero());
  EXPECT_EQ(f.position, hip);
  EXPECT_DOUBLE_EQ(f.radius, 0.004);
  EXPECT_DOUBLE_EQ(free_feel(hip, -0.1).radius, 0);
  const models::haptic::LocalModel m = local_model(force_feedback("ball", "omni", 7, StepStamp{}, f));
  EXPECT_TRUE(models::haptic::covers(m, hip + Eigen::Vector3d(0.003, 0, 0)));
  const double dt = 0.001;
  EXPECT_TRUE(answer_covered(f, 7, hip + Eigen::Vector3d(0, 0.003, 0), 8, dt));
  EXPECT_FALSE(answer_covered(f, 7, hip + Eigen::Vector3d(0, 0.005, 0), 8, dt));  // out of the free ball
  EXPECT_TRUE(answer_covered(f, 7, hip, 17, dt));                                 // 10 ms: half the horizon
  EXPECT_FALSE(answer_covered(f, 7, hip, 18, dt));
  EXPECT_FALSE(answer_covered(free_feel(hip, 0), 7, hip, 8, dt));
  const Feel touching = contact_feel({0, 0, 1}, hip, {0, 0, 1}, 500, 0.002, kContactModelRadius);
  EXPECT_FALSE(answer_covered(touching, 7, hip, 8, dt));
}

}  // namespace
}  // namespace hcosim::adapters::device
