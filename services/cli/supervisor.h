// hcosim up's supervisor: starts a deployment's services as processes,
// reaps them, restarts or lets go of a failed one by its on_failure policy,
// stops them all, and removes the shared memory a killed one left behind.
// It knows no DDS: whether a service's loop has run comes from the watcher.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "adapters/deployment.h"

namespace hcosim::services::cli {

// One service process.
struct Child {
  Child(std::string name_, std::string exe_, std::vector<std::string> args_,
        adapters::OnFailure policy_ = adapters::OnFailure::kStopAll)
      : name(std::move(name_)), exe(std::move(exe_)), args(std::move(args_)), policy(policy_) {}
  std::string name;
  std::string exe;
  std::vector<std::string> args;
  adapters::OnFailure policy = adapters::OnFailure::kStopAll;
  pid_t pid = -1;
  int status = 0;  // waitpid status once reaped
  bool reaped = false;
  int restarts = 0;
  std::string env;        // one NAME=VALUE added to its environment ("" none)
  bool observer = false;  // adapters::observes: never ends a lockstep run by itself, so not waited for
};

// build/bin/hcosim_<kind>, searched in $HCOSIM_SERVICE_PATH, then beside
// this program; a ConfigError at FILE:LINE naming the known kinds if none.
std::string find_service(const std::string& kind, const std::string& file, int line);
// `name` in $PATH; throws std::runtime_error saying it is `what` when absent.
std::string find_program(const std::string& name, const std::string& what);

// "exit status 3", "killed by signal 9 (Killed)".
std::string describe(int status);

// The last line a service wrote to its log: its error, when it failed.
std::string last_line(const std::filesystem::path& log);

class Supervisor {
 public:
  // Each child's output goes to logs/NAME.log. In lockstep a follower
  // exiting 0 has seen the last tick: the clock's exit ends the run.
  Supervisor(std::filesystem::path logs, adapters::Mode mode);
  // Stops whatever still runs.
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;

  // Spawns `c` with its output in its log; returns its pid.
  pid_t start(Child c);

  // Reaps the children that exited since the last call and applies each
  // one's policy: restart (up to adapters::kMaxRestarts; never one refused
  // with exit status 2 before `ran(name)`), ignore, or end the run.
  // Returns why the run ends ("" to go on); appends what to tell the user
  // (restarts, ignored failures, the failed services' last log lines) to
  // `said`.
  std::string poll(const std::function<bool(const std::string&)>& ran, std::string& said);

  // SIGTERM to every running child, SIGKILL after kStopGraceS.
  void stop();

  // After stop(): waits for a background clean, and if a child was killed
  // removes the shared memory it left on `domain`.
  void clean(int domain);

  // 1 if a child failed (our SIGTERM at the end is no failure), else 0.
  int code() const;
  // The failed children's last log lines not yet told.
  std::string last_words() { return std::exchange(last_words_, ""); }
  const std::vector<Child>& children() const { return children_; }
  std::filesystem::path log_of(const std::string& name) const { return logs_ / (name + ".log"); }

  static constexpr double kStopGraceS = 2.0;

 private:
  std::vector<Child*> reap();
  bool all_reaped() const;
  void restart(Child& c);

  std::filesystem::path logs_;
  adapters::Mode mode_;
  std::vector<Child> children_;
  bool failed_ = false;   // an ignored failure: the run goes on, its exit status is 1
  bool crashed_ = false;  // some process died by a signal: its shared memory stays behind
  std::string last_words_;
  pid_t cleaner_ = -1;  // a running `fastdds shm clean`, or -1
  int next_id_ = 0;     // restarts so far, for participant ids
};

}  // namespace hcosim::services::cli
