// The rigid body service's loop without DDS: a device state pressing a
// body is answered with its coupling's force and that force is owed to the
// body, which it pushes; far away each body answers free space, and in
// real time once only while that answer still covers the stylus; resting
// bodies are published when they fall asleep and then at a slower
// repeat; lockstep answers the kept state, its velocity zeroed once old;
// crosscheck mode tells each body's divergence from MuJoCo.
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "services/rigid/body_server.h"
#include "tests/support/samples.h"

namespace hcosim::services::rigid {
namespace {

adapters::rigid::RigidConfig config(const std::string& extra = "") {
  return adapters::rigid::rigid_config(
      adapters::Config::parse("device: omni\n" + extra +
                                  "bodies:\n"
                                  "  - {name: ball, shape: sphere, size: 0.02, centre: [0, 0, 0.02]}\n"
                                  "  - {name: box, shape: cube, size: 0.02, centre: [0.1, 0, 0.02]}\n",
                              "params.yaml", "params"));
}

using tests::haptic_state;
using tests::stamp;

// Every answer to one state, by source.
std::vector<ForceFeedback> answers(BodyServer& server, const HapticState& s, std::uint64_t step) {
  std::vector<ForceFeedback> out;
  server.answer(s, stamp(step), [&](ForceFeedback& f) { out.push_back(f); });
  return out;
}

TEST(BodyServer, APressIsAnsweredAndItsForceOwedToTheBodyPushesIt) {
  BodyServer server(config(), 1e-3, false);
  ASSERT_EQ(server.size(), 2u);
  const Eigen::Vector3d start = server.body(0).x;
  // The stylus held 5 mm inside the ball's -x side for 50 ticks.
  std::vector<ForceFeedback> first;
  for (std::uint64_t k = 0; k < 50; ++k) {
    const std::vector<ForceFeedback> a = answers(server, haptic_state(k, {-0.015, 0, 0.02}), k);
    ASSERT_EQ(a.size(), 2u) << "lockstep answers every body every state";
    if (k == 0) first = a;
    server.step((k + 1) * 1e-3, stamp(k + 1));
  }
  EXPECT_EQ(first[0].source().to_string(), "ball");
  EXPECT_EQ(first[0].device().to_string(), "omni");
  EXPECT_TRUE(first[0].in_contact());
  EXPECT_LT(first[0].force().x(), 0) << "the ball pushes the stylus back along -x";
  EXPECT_FALSE(first[1].in_contact()) << "the box is 10 cm away";
  EXPECT_GT(server.body(0).x.x(), start.x()) << "the force owed to the ball moved it along +x";
  EXPECT_DOUBLE_EQ(server.body(1).x.x(), 0.1) << "nothing touched the box";
}

TEST(BodyServer, InRealTimeAFreeSpaceAnswerIsNotRepeatedWhileItCovers) {
  BodyServer server(config(), 1e-3, true);
  const Eigen::Vector3d far(0, 0, 0.3);
  const std::vector<ForceFeedback> first = answers(server, haptic_state(0, far), 0);
  ASSERT_EQ(first.size(), 2u);
  for (const ForceFeedback& f : first) EXPECT_FALSE(f.in_contact());
  // The next ticks' HIPs are still covered by those free-space answers.
  EXPECT_TRUE(answers(server, haptic_state(1, far), 1).empty());
  EXPECT_TRUE(answers(server, haptic_state(2, far), 2).empty());
  // Far past the horizon, each body is answered again.
  EXPECT_EQ(answers(server, haptic_state(100, far), 100).size(), 2u);
  const std::string report = tests::written([&](std::FILE* out) { server.report(out, "bodies"); });
  EXPECT_NE(report.find("bodies: 4 body-states left to a free-space answer"), std::string::npos) << report;
  EXPECT_NE(report.find("0 states in contact"), std::string::npos) << report;
  EXPECT_NE(report.find("ball: sphere at ["), std::string::npos) << report;
}

TEST(BodyServer, ASleepingBodyIsPublishedWhenItFallsAsleepThenEveryRepeat) {
  BodyServer server(config(), 1e-3, false);
  int published_asleep = 0, steps_asleep = 0;
  double first_asleep = -1, last_asleep = -1;
  for (std::uint64_t k = 1; k <= 3000; ++k) {
    const double now = k * 1e-3;
    const BodyServer::Outputs& out = server.step(now, stamp(k));
    EXPECT_TRUE(out.divergences.empty()) << "no MuJoCo beside the analytic model";
    const bool asleep = server.body(0).sleeping;
    steps_asleep += asleep;
    for (const RigidBodyState& s : out.states) {
      if (s.body().to_string() != "ball" || !asleep) continue;
      if (first_asleep < 0) first_asleep = now;
      ++published_asleep, last_asleep = now;
    }
  }
  ASSERT_GT(steps_asleep, 1000) << "a ball resting on the marker falls asleep";
  ASSERT_GT(first_asleep, 0);
  EXPECT_NEAR(published_asleep, 1 + (last_asleep - first_asleep) / BodyServer::kSleepingRepeat, 1.01);
  EXPECT_LT(published_asleep, steps_asleep / 50);
}

TEST(BodyServer, LockstepAnswersTheKeptStateWithoutItsVelocityOnceOld) {
  BodyServer server(config(), 1e-3, false);
  std::vector<ForceFeedback> out;
  const auto write = [&](ForceFeedback& f) { out.push_back(f); };
  server.answer_kept(0, stamp(0), write);
  EXPECT_TRUE(out.empty()) << "nothing kept yet";
  HapticState s = haptic_state(7, {-0.015, 0, 0.02});
  s.velocity(adapters::device::to_idl({0.5, 0, 0}));
  server.keep(s, 0);
  server.answer_kept(0.001, stamp(1), write);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].answers_seq(), 7u);
  const double moving = out[0].force().x();
  out.clear();
  server.answer_kept(0.1, stamp(100), write);  // long after: the stylus has stopped
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NE(out[0].force().x(), moving) << "the coupling's damping no longer sees the old velocity";
}

TEST(BodyServer, CrosscheckTellsEachBodysDivergenceFromMujoco) {
  BodyServer server(config("backend: crosscheck\n"), 1e-3, false);
  std::size_t divergences = 0;
  for (std::uint64_t k = 1; k <= 50; ++k) {
    const BodyServer::Outputs& out = server.step(k * 1e-3, stamp(k));
    EXPECT_EQ(out.divergences.size(), out.states.size());
    divergences += out.divergences.size();
    for (const RigidDivergence& d : out.divergences) EXPECT_LT(d.position_m(), 1e-3);
  }
  EXPECT_EQ(divergences, 100u);
}

}  // namespace
}  // namespace hcosim::services::rigid
