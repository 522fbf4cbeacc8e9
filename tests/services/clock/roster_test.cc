#include "services/clock/roster.h"

#include <gtest/gtest.h>

namespace hcosim::services::clock {
namespace {

constexpr std::int64_t kS = 1000000000;

TEST(Roster, WaitsForFollowersToJoinLongerForThoseStarting) {
  Roster r({"a", "b"}, 0);
  EXPECT_EQ(r.join_failure(30 * kS, 1, {"b"}), "");
  EXPECT_EQ(r.join_failure(31 * kS, 1, {"b"}),
            "after 30 s only 1 of 2 followers joined (a, b); not yet reading ticks: b");
  r.status("b", true);
  r.status("recorder", true);  // not a follower: no longer wait, nor named
  EXPECT_EQ(r.join_failure(119 * kS, 1, {}), "");
  EXPECT_EQ(r.join_failure(121 * kS, 1, {}), "after 120 s only 1 of 2 followers joined (a, b); still starting: b");
  r.status("b", false);
  EXPECT_NE(r.join_failure(31 * kS, 2, {}), "");
}

TEST(Roster, AStepIsCompleteWhenEveryFollowerAnsweredItAndNoStaleAnswerCounts) {
  Roster r({"a", "b"}, 0);
  r.tick(0, 0);
  EXPECT_FALSE(r.complete());
  r.done(0, "a");
  r.done(0, "stranger");
  EXPECT_FALSE(r.complete());
  r.done(0, "b");
  EXPECT_TRUE(r.complete());
  r.tick(1, kS);
  r.done(0, "a"), r.done(0, "b");  // late copies of the last step's answers
  EXPECT_FALSE(r.complete());
  r.done(1, "a"), r.done(1, "b");
  EXPECT_TRUE(r.complete());
}

TEST(Roster, AStepTooLateNamesWhoHasNotAnswered) {
  Roster r({"a", "b", "c"}, 0);
  r.tick(7, 5 * kS);
  r.done(7, "b");
  EXPECT_EQ(r.step_failure(15 * kS), "");
  EXPECT_EQ(r.step_failure(15 * kS + 1), "step 7: no StepDone from a, c after 10 s");
  r.done(7, "a"), r.done(7, "c");
  EXPECT_EQ(r.step_failure(60 * kS), "");  // complete: never late
}

TEST(Roster, NoFollowersNeverWaits) {
  Roster r({}, 0);
  r.tick(0, 0);
  EXPECT_TRUE(r.complete());
  EXPECT_EQ(names({}), "");
  EXPECT_EQ(names({"x", "y"}), "x, y");
}

}  // namespace
}  // namespace hcosim::services::clock
