// A service's Recordings keep the hcosim up participants it discovers and
// which of them record (by name, and forget them when they go);
// unreached() names the writers that do not reach each recording yet,
// until a reader of theirs matches.
#include <chrono>
#include <memory>
#include <thread>

#include <gtest/gtest.h>

#include "services/runtime/endpoint.h"
#include "services/runtime/recordings.h"
#include "services/runtime/service.h"

namespace hcosim::services::runtime {
namespace {

// A domain of its own: the other runtime tests' participants on 30 would
// match these writers.
constexpr int kRecordingsDomain = 31;

// Polls `done` for up to 5 s.
template <class Done>
bool within_5_s(Done&& done) {
  const std::int64_t deadline = mono_ns() + 5'000'000'000;
  while (!done() && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  return done();
}

TEST(Recordings, WritersReachARecordingOnceItsReadersMatch) {
  Recordings recordings;
  Participant service(kRecordingsDomain, "unit_follower", default_qos_file(), &recordings);
  Writer<HapticState> states(service);
  Writer<ForceFeedback> forces(service);
  // Another participant that reads both is no recording.
  Participant other(kRecordingsDomain, "unit_other");
  Reader<HapticState> other_states(other);
  Reader<ForceFeedback> other_forces(other);
  ASSERT_TRUE(within_5_s([&] { return states.matched() == 1 && forces.matched() == 1; }));
  EXPECT_TRUE(recordings.prefixes().empty());
  EXPECT_TRUE(unreached(service, recordings.prefixes()).empty());

  // An up that does not record is counted, and not waited for.
  Participant up(kRecordingsDomain, kUpParticipant);
  ASSERT_TRUE(within_5_s([&] { return recordings.ups() == 1; }));
  EXPECT_TRUE(recordings.prefixes().empty());

  auto recording = std::make_unique<Participant>(kRecordingsDomain, kRecordingParticipant);
  auto recorded_states = std::make_unique<Reader<HapticState>>(*recording);
  ASSERT_TRUE(within_5_s([&] { return recordings.prefixes().size() == 1; }));
  EXPECT_EQ(recordings.ups(), 2);
  // Its reader of states matches; nothing of it reads forces yet.
  ASSERT_TRUE(within_5_s([&] { return states.matched() == 2; }));
  EXPECT_EQ(unreached(service, recordings.prefixes()), std::vector<std::string>{TopicOf<ForceFeedback>::name});
  {
    Reader<ForceFeedback> recorded_forces(*recording);
    EXPECT_TRUE(within_5_s([&] { return unreached(service, recordings.prefixes()).empty(); }));
  }
  // A reader gone leaves its writer unreached again.
  EXPECT_TRUE(within_5_s([&] { return unreached(service, recordings.prefixes()).size() == 1; }));

  // The recording gone (its reader first), nothing is waited for.
  recorded_states.reset();
  recording.reset();
  EXPECT_TRUE(within_5_s([&] { return recordings.prefixes().empty(); }));
  EXPECT_EQ(recordings.ups(), 1);
  EXPECT_TRUE(unreached(service, recordings.prefixes()).empty());
}

}  // namespace
}  // namespace hcosim::services::runtime
