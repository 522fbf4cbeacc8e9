#include "services/cli/supervisor.h"

#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::services::cli {
namespace {

using adapters::Mode;
using adapters::OnFailure;

Child shell(const std::string& name, const std::string& script,
            adapters::OnFailure policy = adapters::OnFailure::kStopAll) {
  return Child{name, "/bin/sh", {"-c", script}, policy};
}

// Polls until the run ends (or 20 s); returns the reason and appends what
// was said to `said`.
std::string run_until_end(Supervisor& s, std::string& said, const std::function<bool(const std::string&)>& ran) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::string reason;
  while (reason.empty() && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    reason = s.poll(ran, said);
  }
  return reason;
}

const auto kRan = [](const std::string&) { return true; };

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Supervisor, AServiceThatFinishesEndsARealtimeRun) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kRealtime);
  s.start(shell("a", "echo hello"));
  s.start(shell("b", "sleep 30"));
  std::string said;
  EXPECT_EQ(run_until_end(s, said, kRan), "service 'a' finished");
  s.stop();
  EXPECT_EQ(s.code(), 0);  // b stopped by our SIGTERM: no failure
  EXPECT_EQ(read(s.log_of("a")), "hello\n");
  EXPECT_TRUE(WIFSIGNALED(s.children()[1].status));
}

TEST(Supervisor, RestartsAFailedServiceUpToTheLimitKeepingItsLog) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kRealtime);
  s.start(shell("a", "echo boom; exit 3", adapters::OnFailure::kRestart));
  std::string said;
  EXPECT_EQ(run_until_end(s, said, kRan), "service 'a' ended (exit status 3) after 3 restarts");
  EXPECT_EQ(s.children()[0].restarts, adapters::kMaxRestarts);
  EXPECT_NE(said.find("service 'a' ended (exit status 3); restarting it (3 of 3)\n  a: boom\n"), std::string::npos)
      << said;
  const std::string log = read(s.log_of("a"));
  for (int k = 1; k <= 3; ++k)
    EXPECT_NE(log.find("--- hcosim up: ended (exit status 3), restart " + std::to_string(k) + " ---"),
              std::string::npos)
        << log;
  EXPECT_EQ(s.last_words(), "  a: boom\n");
  s.stop();
  EXPECT_EQ(s.code(), 1);
}

TEST(Supervisor, ARefusedConfigurationIsNotRestarted) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kRealtime);
  s.start(shell("a", "echo 'a.yaml:3:5: unknown key' >&2; exit 2", adapters::OnFailure::kRestart));
  std::string said;
  EXPECT_EQ(run_until_end(s, said, [](const std::string&) { return false; }),
            "service 'a' ended (exit status 2 before its loop ran; a refused configuration is not restarted)");
  EXPECT_EQ(s.children()[0].restarts, 0);
  EXPECT_EQ(s.last_words(), "  a: a.yaml:3:5: unknown key\n");
}

TEST(Supervisor, AnIgnoredFailureLetsTheOthersRunOnAndStillFailsTheRun) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kRealtime);
  s.start(shell("a", "exit 4", adapters::OnFailure::kIgnore));
  s.start(shell("b", "sleep 30"));
  std::string said;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (said.empty() && std::chrono::steady_clock::now() < until) {
    EXPECT_EQ(s.poll(kRan, said), "");
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(said, "hcosim up: service 'a' ended (exit status 4); on_failure: ignore, the others run on\n");
  EXPECT_FALSE(s.children()[1].reaped);
  s.stop();
  EXPECT_EQ(s.code(), 1);
}

TEST(Supervisor, KillsAServiceThatIgnoresSigterm) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kRealtime);
  s.start(shell("deaf", "trap '' TERM; echo ready; while :; do sleep 0.05; done"));
  while (read(s.log_of("deaf")).empty()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const auto t0 = std::chrono::steady_clock::now();
  s.stop();
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(s.children()[0].reaped);
  EXPECT_TRUE(WIFSIGNALED(s.children()[0].status));
  EXPECT_EQ(WTERMSIG(s.children()[0].status), SIGKILL);
  EXPECT_GE(took, Supervisor::kStopGraceS);
  EXPECT_EQ(s.code(), 1);
  EXPECT_EQ(describe(s.children()[0].status), "killed by signal 9 (Killed)");
}

TEST(Supervisor, InLockstepTheClocksExitEndsTheRun) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kLockstep);
  s.start(shell("follower", "exit 0"));
  s.start(shell("clock", "sleep 0.3"));
  std::string said;
  EXPECT_EQ(run_until_end(s, said, kRan), "lockstep run complete");
  EXPECT_TRUE(s.children()[0].reaped && s.children()[1].reaped);
  EXPECT_EQ(s.code(), 0);
  EXPECT_EQ(said, "");
}

// An observer (the Foxglove bridge) never exits by itself: once the clock
// and the followers have, the run ends without waiting out the grace
// period for it, and stop() ends it.
TEST(Supervisor, InLockstepTheRunsEndDoesNotWaitForAnObserver) {
  tests::TempDir dir;
  Supervisor s(dir.path, adapters::Mode::kLockstep);
  s.start(shell("follower", "exit 0"));
  Child observer = shell("fox", "exec sleep 30");
  observer.observer = true;
  s.start(observer);
  s.start(shell("clock", "sleep 0.3"));
  std::string said;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(run_until_end(s, said, kRan), "lockstep run complete");
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(took, Supervisor::kStopGraceS) << "waited out the grace period for the observer";
  EXPECT_FALSE(s.children()[1].reaped);
  s.stop();
  EXPECT_TRUE(s.children()[1].reaped);
}

TEST(Supervisor, AnUnknownKindNamesTheFileLineAndTheKnownKinds) {
  const std::string e = tests::message_of<adapters::ConfigError>([] { find_service("nosuch", "d.yaml", 7); });
  EXPECT_EQ(e.rfind("d.yaml:7:1: no service of kind 'nosuch' (known kinds: ", 0), 0u) << e;
}

}  // namespace
}  // namespace hcosim::services::cli
