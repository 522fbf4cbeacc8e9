// The frame every hcosim service runs in: options, participant, time,
// heartbeat, validation counts and clean shutdown. A service provides a
// step function; the runtime decides when it runs.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "adapters/deployment.h"
#include "adapters/validate.h"
#include "services/runtime/endpoint.h"
#include "services/runtime/participant.h"
#include "services/runtime/realtime.h"
#include "services/runtime/recordings.h"
#include "services/runtime/stats.h"

namespace hcosim::services::runtime {

// Command-line options shared by every service executable.
struct Options {
  std::string name;                                 // --name: service name, key of its ServiceStatus
  int domain = 0;                                   // --domain
  adapters::Mode mode = adapters::Mode::kRealtime;  // --mode realtime|lockstep
  double rate_hz = 0;                               // --rate: step rate, Hz (required)
  double step_s = 0;                                // --step: base step, s (default 1/rate)
  double duration_s = 0;                            // --duration: s; 0 = until stopped (realtime only)
  std::string qos_file;                             // --qos (default: default_qos_file())
  std::string deployment;                           // --deployment: file holding this service's params
  std::string host;         // --host: its host in the deployment's hosts ("": one machine runs them all)
  std::string out = "out";  // --out: folder for the files a service writes (videos, plots)
  Scheduling scheduling;    // --priority (SCHED_FIFO 1..99, 0 normal), --cpu: real time only
};

// A service's main: parses its command line into Options (CLI11; --help
// lists them) and runs `run` inside guarded_main. `what` is one line
// saying what the service does, for its help.
int service_main(const char* program, const char* what, int argc, char** argv,
                 const std::function<int(const Options&)>& run);

// One step of a service.
struct Tick {
  std::uint64_t step;        // base-step index (StepStamp.step of outputs)
  std::int64_t sim_time_ns;  // simulated time at this step
  double dt_s;               // time since this service's previous step, s
  double late_us = 0;        // real time: how late the step woke after it was due, us (0 in lockstep)
};

class Service {
 public:
  explicit Service(Options options);

  // Writer and reader on this service's participant. Readers validate with
  // hcosim::validate and count refusals in this service's status.
  template <class T>
  Writer<T> writer(const std::string& profile = TopicOf<T>::qos) {
    return Writer<T>(participant_, profile);
  }
  // `depth` > 0 keeps that many samples per instance (see Reader).
  template <class T>
  Reader<T> reader(const std::string& profile = TopicOf<T>::qos, int depth = 0) {
    return Reader<T>(
        participant_, [](const T& s) { return adapters::validate(s); }, &rejections_, profile, depth);
  }

  // The admissible samples of `r` for this step: in real time all that
  // arrived; in lockstep those stamped before the tick's step, which have
  // all arrived by then (every service waits for its outputs to be
  // acknowledged before it reports a step done), so a step's inputs do
  // not depend on delivery order.
  template <class T, class F>
  std::size_t take(Reader<T>& r, const Tick& tick, F&& f) {
    return options_.mode == adapters::Mode::kLockstep ? r.take_before(tick.step, std::forward<F>(f))
                                                      : r.take(std::forward<F>(f));
  }

  // This service's params from the deployment file (empty without one).
  const adapters::Config& params() const { return params_; }

  // StepStamp for outputs computed at `tick`.
  StepStamp stamp(const Tick& tick) const;

  // Counts an output not computed because no reader is matched.
  void skip_output() { ++outputs_skipped_; }
  // Counts an output dropped because the CPU was short (a frame whose
  // predecessor was still being made). Any thread. A real-time loop's
  // skipped ticks (after an overrun) count here too.
  void shed_output() { ++outputs_shed_; }

  // What the constructor's thread got of --priority and --cpu: the
  // scheduling that the threads it creates inherit, Fast DDS's included
  // (realtime.h). Reported in every ServiceStatus.
  const std::string& scheduling() const { return scheduling_; }
  // A haptic device's loop figures, reported in its ServiceStatus.
  void set_haptic_figures(double in_tick_ratio, double force_error_p99_n) {
    in_tick_ratio_ = in_tick_ratio, force_error_p99_n_ = force_error_p99_n;
  }

  // Calls step() at the configured rate, from the wall clock (realtime) or
  // the lockstep master's ClockTick (lockstep), until SIGINT/SIGTERM, the
  // duration, or the master's last tick. Returns the process exit status.
  int run(const std::function<void(const Tick&)>& step);

  // Waits (0.5 s at most) until every writer of the participant has its
  // samples acknowledged, so that the writers can be deleted safely: Fast
  // DDS 2.9.1 can loop forever deleting a writer whose periodic heartbeat,
  // active while samples are unacknowledged, fires meanwhile (fixed in
  // 2.10, eProsima/Fast-DDS#4076; a lockstep writer's heartbeat comes every
  // 1 ms). run() ends with it; a service with its own loop calls it last.
  void settle();

  // Ends a real-time run after the current step (e.g. a video that has
  // run out). A lockstep follower cannot leave early: it runs on to the
  // master's last tick.
  void finish() { finished_ = true; }

  // ServiceStatus.state: "starting" from the constructor until the loop
  // runs (a service may build its model for seconds in between), then
  // "running", and "stopping" in the last report.
  enum class Phase { kStarting, kRunning, kStopping };

  // For services that drive their own loop (the lockstep master): record
  // one step; publish status if a period has passed or the phase changed.
  void record_step(double jitter_us, double step_us, bool overrun);
  void heartbeat(std::int64_t sim_time_ns, std::uint64_t step, Phase phase = Phase::kRunning);

  const Options& options() const { return options_; }
  const adapters::Deployment& deployment() const { return deployment_; }
  Participant& participant() { return participant_; }

 private:
  int run_realtime(const std::function<void(const Tick&)>& step);
  int run_lockstep(const std::function<void(const Tick&)>& step);
  void wait_for_recordings();

  Options options_;
  std::uint64_t period_steps_;       // base steps per service step
  adapters::Deployment deployment_;  // --deployment's file (empty without one)
  std::string scheduling_;           // before the participant, whose threads inherit it
  Recordings recordings_;            // the participant's discovery listener
  Participant participant_;
  adapters::Config params_;
  Writer<ServiceStatus> status_;
  Rejections rejections_;
  Window jitter_us_, step_us_;
  std::uint64_t steps_ = 0, overruns_ = 0, outputs_skipped_ = 0;
  std::atomic<std::uint64_t> outputs_shed_{0};
  double in_tick_ratio_ = 0, force_error_p99_n_ = 0;
  std::uint64_t steps_at_heartbeat_ = 0;
  std::int64_t last_heartbeat_ns_ = 0;  // 0 until the first heartbeat
  Phase phase_ = Phase::kStarting;      // of the last heartbeat
  bool finished_ = false;
};

// SIGINT and SIGTERM set a flag instead of killing the process, so loops
// end and every DDS entity is deleted. Installed by Service itself.
void install_stop_handlers();
bool stop_requested();

// Runs body() and turns exceptions into a message on stderr and an exit
// status: 2 for usage and configuration errors, 1 for anything else.
int guarded_main(const char* program, const std::function<int()>& body);

// Monotonic and wall clocks, ns.
std::int64_t mono_ns();
std::int64_t wall_ns();

}  // namespace hcosim::services::runtime
