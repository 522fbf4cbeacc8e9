// The lockstep master's bookkeeping, without DDS (docs/cosimulation.md):
// which followers it waits for before tick 0, how long, and which of them
// have answered the step it ticked last. Times are the caller's monotonic
// clock in ns. services/clock/main.cc wires it to ClockTick, StepDone and
// ServiceStatus.
#pragma once

#include <cstdint>
#include <set>
#include <string>

namespace hcosim::services::clock {

// Joins names for messages: "a, b".
std::string names(const std::set<std::string>& s);

class Roster {
 public:
  static constexpr double kJoinTimeoutS = 30;
  // A follower that says it is starting (building its model, which under a
  // sanitizer or for a large mesh takes longer than kJoinTimeoutS) is
  // waited for this long instead, as `hcosim up` waits for it.
  static constexpr double kStartTimeoutS = 120;
  static constexpr double kStepTimeoutS = 10;

  // `followers`: the services that answer every step; `now_ns`: when the
  // clock began to wait for them.
  Roster(std::set<std::string> followers, std::int64_t now_ns);
  const std::set<std::string>& followers() const { return followers_; }

  // A service's latest status: whether it says it is starting. Other
  // services' are ignored.
  void status(const std::string& service, bool starting);
  // "" while the followers may still join at `now_ns`; else why the clock
  // gives up: `joined` of them answer StepDone, `deaf` do not hear ticks yet.
  std::string join_failure(std::int64_t now_ns, int joined, const std::set<std::string>& deaf) const;

  // Step `step` was ticked at `now_ns`: every follower is waited for.
  void tick(std::uint64_t step, std::int64_t now_ns);
  // A follower's StepDone; one for another step is stale and ignored.
  void done(std::uint64_t step, const std::string& service);
  bool complete() const { return waiting_.empty(); }
  // "" until the step's answers are kStepTimeoutS late at `now_ns`; then
  // who has not answered.
  std::string step_failure(std::int64_t now_ns) const;

 private:
  std::set<std::string> followers_;
  std::int64_t join_start_ns_;
  std::set<std::string> starting_;  // followers whose latest status says starting
  std::uint64_t step_ = 0;
  std::int64_t step_start_ns_ = 0;
  std::set<std::string> waiting_;  // followers yet to answer step_
};

}  // namespace hcosim::services::clock
