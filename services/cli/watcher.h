// hcosim up's watcher: from the participants discovered on the domain and
// the services' ServiceStatus, it tells when every service has joined and
// when each runs its loop (the duration of a real-time run counts from
// then), and writes the run's progress line. It reads no DDS itself: up
// feeds it what its participant hears.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "idl/status.h"

namespace hcosim::services::cli {

class Watcher {
 public:
  // `names`: the services (and the clock) whose participants carry those names.
  // `tty`: the progress line is rewritten in place, else a new line every kLogProgressS.
  Watcher(std::vector<std::string> names, int domain, bool tty);

  // A participant discovered on the domain (from Fast DDS's thread), and
  // `where` it says it listens (its GUID and unicast locators), which the
  // warning that a service still starts repeats for every participant: a
  // service that joined but is never heard from may share its ports.
  void joined(const std::string& participant, const std::string& where = "");
  // One ServiceStatus sample (validated).
  void status(const ServiceStatus& s);

  // The text to print at `now_ns`, `waited_s` after the services started:
  // who joined or still starts (once each), the progress line when due.
  std::string update(double waited_s, std::int64_t now_ns);
  // Ends an in-place progress line before other output.
  std::string finish();

  // Whether `name` has reported that its loop runs (or has run).
  bool running(const std::string& name) const { return ran_.count(name) > 0; }
  // Every service runs its loop, or kStartWaitS has passed.
  bool started() const { return all_running_; }

  static constexpr double kJoinWaitS = 10.0;    // s before naming the services that have not joined
  static constexpr double kStartWaitS = 120.0;  // s the duration waits for every service's loop to run
  static constexpr double kLogProgressS = 5;    // s between progress lines in a log

 private:
  std::string progress(std::int64_t now_ns);

  std::vector<std::string> names_;
  int domain_;
  bool tty_;
  std::mutex joined_mutex_;
  std::map<std::string, std::string> joined_;  // participant name: where it listens
  std::map<std::string, ServiceStatus> latest_;
  std::set<std::string> ran_;
  std::string scheduling_;                    // services' scheduling lines not yet printed
  std::int64_t sim_ns_ = 0, printed_ns_ = 0;  // the furthest service's simulated time
  double factor_ = 0;                         // simulated over wall time between its last two reports
  bool shown_ = false;                        // a progress line is on screen, not ended
  bool all_joined_ = false, join_warned_ = false, all_running_ = false, start_warned_ = false;
};

}  // namespace hcosim::services::cli
