#include "services/cli/watcher.h"

#include <gtest/gtest.h>

namespace hcosim::services::cli {
namespace {

constexpr std::int64_t kS = 1'000'000'000;

ServiceStatus status(const std::string& name, const std::string& state, double sim_s, double wall_s,
                     std::uint64_t steps) {
  ServiceStatus s;
  s.service(name);
  s.state(state);
  s.stamp().sim_time_ns(std::int64_t(sim_s * kS));
  s.stamp().wall_time_ns(std::int64_t(wall_s * kS));
  s.steps(steps);
  s.rate_achieved_hz(1000);
  s.overruns(3);
  s.scheduling("SCHED_FIFO 30");
  return s;
}

TEST(Watcher, SaysWhenEveryServiceHasJoinedOrNamesTheMissingOnce) {
  Watcher w({"a", "b"}, 7, false);
  w.joined("a");
  w.joined("hcosim_up");
  EXPECT_EQ(w.update(1.0, 1 * kS), "");
  EXPECT_EQ(w.update(10.5, 2 * kS), "hcosim up: after 10 s still no status from: b\n");
  EXPECT_EQ(w.update(10.6, 3 * kS), "");
  w.joined("b");
  // Past kJoinWaitS, joined but with no loop running yet: said once too.
  EXPECT_EQ(w.update(12.25, 4 * kS),
            "hcosim up: every service joined domain 7 in 12.25 s\nhcosim up: still starting after 10 s: a, b\n");
  EXPECT_EQ(w.update(12.5, 5 * kS), "");
}

TEST(Watcher, TheRunStartsWhenEveryLoopRuns) {
  Watcher w({"a", "b"}, 7, false);
  w.joined("a"), w.joined("b");
  w.status(status("a", "running", 0, 100, 0));
  w.status(status("b", "starting", 0, 100, 0));
  EXPECT_EQ(w.update(0.5, 1 * kS),
            "  a                scheduling: SCHED_FIFO 30\n  b                scheduling: SCHED_FIFO 30\n"
            "hcosim up: every service joined domain 7 in 0.50 s\n");
  EXPECT_TRUE(w.running("a"));
  EXPECT_FALSE(w.running("b"));
  EXPECT_FALSE(w.started());
  EXPECT_EQ(w.update(10.5, 2 * kS), "hcosim up: still starting after 10 s: b\n");
  w.status(status("b", "running", 0, 101, 0));
  EXPECT_EQ(w.update(11.0, 3 * kS), "hcosim up: every service running after 11.00 s\n");
  EXPECT_TRUE(w.started());
}

// A service that joined but is never heard from: where every participant
// listens follows the warning, so that two that share ports show it.
TEST(Watcher, AServiceStillStartingIsShownWithWhereEachParticipantListens) {
  Watcher w({"a", "b"}, 7, false);
  w.joined("a", "01.0f.aa, discovery at SHM:[_]:7413, data at SHM:[_]:7415");
  w.joined("b", "01.0f.bb, discovery at SHM:[_]:7413, data at SHM:[_]:7415");
  w.joined("hcosim_up", "01.0f.cc, discovery at SHM:[_]:7411, data at SHM:[_]:7412");
  w.status(status("a", "running", 0, 100, 0));
  w.update(1, 1 * kS);
  EXPECT_EQ(w.update(11, 2 * kS),
            "hcosim up: still starting after 10 s: b\n"
            "hcosim up:   participant a 01.0f.aa, discovery at SHM:[_]:7413, data at SHM:[_]:7415\n"
            "hcosim up:   participant b 01.0f.bb, discovery at SHM:[_]:7413, data at SHM:[_]:7415\n"
            "hcosim up:   participant hcosim_up 01.0f.cc, discovery at SHM:[_]:7411, data at SHM:[_]:7412\n");
  EXPECT_EQ(w.update(12, 3 * kS), "");
}

TEST(Watcher, ARunGoesOnWithoutAServiceThatNeverStarts) {
  Watcher w({"a"}, 7, false);
  w.joined("a");
  w.status(status("a", "starting", 0, 100, 0));
  w.update(1, 1 * kS);
  EXPECT_EQ(w.update(11, 2 * kS), "hcosim up: still starting after 10 s: a\n");
  EXPECT_FALSE(w.started());
  EXPECT_EQ(w.update(Watcher::kStartWaitS + 1, 3 * kS),
            "hcosim up: after 120 s still starting: a; the run goes on without waiting\n");
  EXPECT_TRUE(w.started());
  EXPECT_FALSE(w.running("a"));
}

TEST(Watcher, TheProgressLineHasSimulatedTimeRealTimeFactorAndRates) {
  Watcher w({"a"}, 7, false);
  w.joined("a");
  w.status(status("a", "running", 1.0, 100.0, 1000));
  w.status(status("a", "running", 2.0, 102.0, 2000));  // 1 s of simulation in 2 s of wall time
  EXPECT_EQ(w.update(3, 10 * kS),
            "  a                scheduling: SCHED_FIFO 30\n"
            "hcosim up: every service joined domain 7 in 3.00 s\n"
            "hcosim up: every service running after 3.00 s\n"
            "sim 2.0 s, real-time factor 0.50 | a 1000 Hz, 3 overruns\n");
  // In a log, one line every kLogProgressS.
  EXPECT_EQ(w.update(4, 11 * kS), "");
  EXPECT_EQ(w.update(9, 16 * kS), "sim 2.0 s, real-time factor 0.50 | a 1000 Hz, 3 overruns\n");
}

TEST(Watcher, OnATerminalTheLineIsRewrittenAndEndedBeforeOtherOutput) {
  Watcher w({"a"}, 7, true);
  w.status(status("a", "running", 1.0, 100.0, 1000));
  w.status(status("a", "running", 2.0, 101.0, 2000));
  EXPECT_EQ(w.update(1, 10 * kS),
            "  a                scheduling: SCHED_FIFO 30\nhcosim up: every service running after 1.00 s\n"
            "\rsim 2.0 s, real-time factor 1.00 | a 1000 Hz, 3 overruns\033[K");
  EXPECT_EQ(w.finish(), "\n");
  EXPECT_EQ(w.finish(), "");
}

}  // namespace
}  // namespace hcosim::services::cli
