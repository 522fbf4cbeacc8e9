// The simulated Omni: force limit and saturation count, workspace stops,
// encoder steps and the velocity filter, bad specs refused by name.
#include <gtest/gtest.h>

#include <set>

#include "adapters/device/simulated_omni.h"

namespace hcosim::adapters::device {

using namespace models::haptic;
namespace {

models::haptic::Script still(const Eigen::Vector3d& at, double seconds) {
  models::haptic::Script s;
  s.start = at;
  models::haptic::Action hold;
  hold.kind = models::haptic::Action::Kind::hold;
  hold.duration = seconds;
  s.actions = {hold};
  return s;
}

TEST(HapticDevice, ForceIsClampedToTheMaximumAndSaturationCounted) {
  SimulatedOmni omni({}, {}, still(Eigen::Vector3d::Zero(), 1));
  omni.begin_frame();
  const Eigen::Vector3d out = omni.end_frame({0, 0, 10});
  EXPECT_DOUBLE_EQ(out.norm(), 3.3);
  EXPECT_NEAR(out.z(), 3.3, 1e-12);
  omni.begin_frame();
  EXPECT_EQ(omni.end_frame({0.5, 0, 0}), Eigen::Vector3d(0.5, 0, 0));
  omni.begin_frame();
  EXPECT_EQ(omni.end_frame({NAN, 0, 0}), Eigen::Vector3d::Zero());
  omni.begin_frame();
  omni.end_frame({1.0, 0, 0});  // above the continuous 0.88 N, below the peak
  EXPECT_EQ(omni.saturated(), 2u);
  EXPECT_EQ(omni.over_continuous(), 2u);
  EXPECT_EQ(omni.frames(), 4u);
}

TEST(HapticDevice, WorkspaceWallsStopTheStylus) {
  models::haptic::Script s = still(Eigen::Vector3d::Zero(), 0);
  models::haptic::Action far;
  far.kind = models::haptic::Action::Kind::move_to;
  far.to = {0.5, -0.5, 0.5};  // far outside 160 x 120 x 70 mm
  far.speed = 0.5;
  s.actions = {far};
  SimulatedOmni omni({}, {}, s);
  while (!omni.finished()) omni.begin_frame(), omni.end_frame(Eigen::Vector3d::Zero());
  for (int k = 0; k < 500; ++k) omni.begin_frame(), omni.end_frame(Eigen::Vector3d::Zero());
  const Frame f = omni.begin_frame();
  EXPECT_NEAR(f.position.x(), 0.080, 1e-4);
  EXPECT_NEAR(f.position.y(), -0.060, 1e-4);
  EXPECT_NEAR(f.position.z(), 0.035, 1e-4);
}

TEST(HapticDevice, PositionsComeInEncoderStepsAndVelocityFollows) {
  models::haptic::Script s = still(Eigen::Vector3d::Zero(), 0);
  models::haptic::Action move;
  move.kind = models::haptic::Action::Kind::move_to;
  move.to = {0.02, 0, 0};
  move.speed = 0.05;
  models::haptic::Action hold;
  hold.kind = models::haptic::Action::Kind::hold;
  hold.duration = 0.5;
  s.actions = {move, hold};
  SimulatedOmni omni({}, {}, s);
  double peak = 0, true_peak = 0;
  while (!omni.finished()) {
    const Frame f = omni.begin_frame();
    const Eigen::Vector3d steps = f.position / 0.055e-3;
    EXPECT_LT((steps - steps.array().round().matrix()).norm(), 1e-6);
    EXPECT_LT((f.position - omni.tip().x).cwiseAbs().maxCoeff(), 0.5 * 0.055e-3 + 1e-12);
    peak = std::max(peak, f.velocity.x());
    true_peak = std::max(true_peak, omni.tip().v.x());
    omni.end_frame(Eigen::Vector3d::Zero());
  }
  // The hand's 5 cm/s with its overshoot; the estimate sees it, within the
  // encoder's noise (one step per tick is 0.055 m/s) after the 50 Hz
  // filter, then rest, short of the target by at most the back-drive
  // friction over the hand's stiffness.
  EXPECT_GT(true_peak, 0.05);
  EXPECT_NEAR(peak, true_peak, 0.02);
  const Frame end = omni.begin_frame();
  EXPECT_NEAR(end.position.x(), 0.02, OmniSpec{}.backdrive_friction / Hand{}.stiffness + 0.055e-3);
  EXPECT_LT(end.velocity.norm(), 1e-3);
}

// A press held on a contact stiffer than the hand: without back-drive
// friction no position between two counts is at rest, and the reported
// position steps between them for as long as the press lasts; with it the
// stylus rests on one count. And friction never drives: the tip's speed
// never turns against the net force's.
TEST(HapticDevice, BackdriveFrictionLetsAHeldPressRestOnOneCount) {
  for (const double friction : {0.0, OmniSpec{}.backdrive_friction}) {
    OmniSpec spec;
    spec.backdrive_friction = friction;
    models::haptic::Script s = still(Eigen::Vector3d(0, 0, -0.003), 1.0);
    s.start = Eigen::Vector3d(0, 0, -0.003);
    SimulatedOmni omni(spec, {}, s);
    std::set<double> seen;  // reported heights over the last half second
    for (int k = 0; k < 1000; ++k) {
      const Frame f = omni.begin_frame();
      // A wall at z = 0 of 2,000 N/m (a count's step is 0.11 N of it).
      const Eigen::Vector3d force(0, 0, f.position.z() < 0 ? -2000 * f.position.z() : 0);
      if (k >= 500) seen.insert(f.position.z());
      omni.end_frame(force);
    }
    if (friction == 0)
      EXPECT_GE(seen.size(), 2u) << "with no friction the press should step between counts";
    else
      EXPECT_EQ(seen.size(), 1u) << "friction " << friction << " N";
  }
}

TEST(HapticDevice, BackdriveFrictionHoldsWithinItsLimitAndSlidesBeyond) {
  OmniSpec spec;
  Tip tip;
  const Hand hand{200, 2};
  // A pull of 0.09 N (0.45 mm from the target) is held where it starts.
  step_tip(spec, hand, Eigen::Vector3d(0.00045, 0, 0), Eigen::Vector3d::Zero(), 1e-3, tip);
  EXPECT_EQ(tip.x, Eigen::Vector3d::Zero());
  EXPECT_EQ(tip.v, Eigen::Vector3d::Zero());
  // 0.2 N moves it, as if 0.1 N pulled with no friction.
  Tip free;
  OmniSpec frictionless = spec;
  frictionless.backdrive_friction = 0;
  step_tip(spec, hand, Eigen::Vector3d(0.001, 0, 0), Eigen::Vector3d::Zero(), 1e-3, tip);
  step_tip(frictionless, hand, Eigen::Vector3d(0.0005, 0, 0), Eigen::Vector3d::Zero(), 1e-3, free);
  EXPECT_GT(tip.v.x(), 0);
  EXPECT_NEAR(tip.v.x(), free.v.x(), 1e-12);
}

TEST(HapticDevice, BadSpecsAreRefusedByName) {
  models::haptic::OmniSpec spec;
  spec.max_force = 0;
  EXPECT_THROW(
      {
        try {
          SimulatedOmni omni(spec, {}, still(Eigen::Vector3d::Zero(), 1));
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("max_force"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::adapters::device
