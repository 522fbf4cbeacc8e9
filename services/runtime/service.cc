#include "services/runtime/service.h"

#include <dirent.h>
#include <execinfo.h>
#include <pthread.h>
#include <semaphore.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "services/runtime/args.h"

namespace hcosim::services::runtime {
namespace {

std::atomic<bool> g_stop{false};
sem_t g_stop_sem;  // posted once, on the first stop request

void on_signal(int) {
  if (!g_stop.exchange(true)) sem_post(&g_stop_sem);
}

// A service still running this long after its stop request prints every
// thread's stack: hcosim up kills it at Supervisor::kStopGraceS (2 s), and
// the log is then the only trace of where its stop hung.
constexpr auto kSlowStop = std::chrono::milliseconds(1500);
constexpr int kStackDepth = 32;
std::atomic<bool> g_stack_done{false};

// SIGUSR2's handler: this thread's stack, on stderr. backtrace_symbols_fd
// allocates nothing, and backtrace() was called once beforehand so that
// it loads nothing here either.
void on_stack_request(int) {
  void* frames[kStackDepth];
  backtrace_symbols_fd(frames, backtrace(frames, kStackDepth), STDERR_FILENO);
  g_stack_done = true;
}

void print_stacks_if_slow(std::string name) {
  while (sem_wait(&g_stop_sem) != 0) {
  }
  std::this_thread::sleep_for(kSlowStop);
  std::fprintf(stderr, "%s: still running %lld ms after its stop request; its threads' stacks:\n", name.c_str(),
               (long long)kSlowStop.count());
  const pid_t self = pid_t(syscall(SYS_gettid));
  DIR* tasks = opendir("/proc/self/task");
  while (dirent* e = tasks ? readdir(tasks) : nullptr) {
    const pid_t tid = std::atoi(e->d_name);
    if (tid <= 0 || tid == self) continue;
    char comm[64] = "?";
    if (FILE* f = std::fopen(("/proc/self/task/" + std::to_string(tid) + "/comm").c_str(), "r")) {
      if (std::fscanf(f, "%63s", comm) != 1) comm[0] = 0;
      std::fclose(f);
    }
    std::fprintf(stderr, "--- thread %d (%s)%s\n", tid, comm, tid == getpid() ? ", the main thread" : "");
    std::fflush(stderr);
    // One thread at a time, so that stacks do not interleave.
    g_stack_done = false;
    if (syscall(SYS_tgkill, getpid(), tid, SIGUSR2) != 0) continue;
    for (int i = 0; i < 100 && !g_stack_done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (tasks) closedir(tasks);
}

// Once per process: the thread that waits for a stop request to be slow.
void watch_stop(const std::string& name) {
  static std::once_flag once;
  std::call_once(once, [&] {
    void* warm[1];
    backtrace(warm, 1);
    struct sigaction sa {};
    sa.sa_handler = on_stack_request;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGUSR2, &sa, nullptr);
    std::thread(print_stacks_if_slow, name).detach();
  });
}

}  // namespace

// Without SA_RESTART, so that sleeps and waits return early on a signal.
void install_stop_handlers() {
  static std::once_flag once;
  std::call_once(once, [] { sem_init(&g_stop_sem, 0, 0); });
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

bool stop_requested() { return g_stop; }

namespace {

constexpr std::int64_t kHeartbeatNs = 1'000'000'000;
// How long a lockstep follower waits for a recording to match its
// writers (matching takes milliseconds; the clock waits 10 s for a step).
constexpr std::int64_t kRecordingWaitNs = 5'000'000'000;
// How long a lockstep follower waits for the next tick once the run has
// begun: the clock gives up on a step after 10 s, so a follower that hears
// nothing for longer has lost the clock (its host gone, or the clock
// stopped) and ends instead of waiting forever.
constexpr std::int64_t kTickWaitNs = 20'000'000'000;

// Base steps per service step. A lockstep follower steps on whole ticks of
// the clock; in real time the period is the rate's own and this only
// rounds stamps, so any rate goes (a 30 fps camera under a 1 ms step).
std::uint64_t steps_per_period(const Options& o) {
  const double ratio = 1.0 / (o.rate_hz * o.step_s);
  const double whole = std::round(ratio);
  if (o.mode == adapters::Mode::kRealtime) return static_cast<std::uint64_t>(std::max(1.0, whole));
  if (whole < 1 || std::abs(ratio - whole) > 1e-6 * whole)
    throw std::invalid_argument("rate " + std::to_string(o.rate_hz) +
                                " Hz is not a whole divisor of the base step rate " + std::to_string(1.0 / o.step_s) +
                                " Hz");
  return static_cast<std::uint64_t>(whole);
}

adapters::Config params_of(const adapters::Deployment& d, const std::string& name) {
  if (d.file.empty()) return adapters::Config("", YAML::Node());
  for (const auto& s : d.services)
    if (s.name == name) return adapters::Config(d.file, s.params);
  // The lockstep master is not an entry of the file.
  if (name == "clock") return adapters::Config(d.file, YAML::Node());
  throw adapters::ConfigError(d.file + ": has no service named '" + name + "'");
}

// A lockstep step has no deadline: nothing to put first, and a FIFO
// thread waiting on the clock would only hold a core from the others.
std::string schedule(const Options& o) {
  if (o.mode == adapters::Mode::kLockstep) return apply({0, o.scheduling.cpu}) + " (lockstep: no deadline)";
  return apply(o.scheduling);
}

}  // namespace

std::int64_t mono_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::int64_t wall_ns() {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int service_main(const char* program, const char* what, int argc, char** argv,
                 const std::function<int(const Options&)>& run) {
  // Line by line: a log shows a service's last words even when it is
  // killed after them (a stop that hung, above).
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  Options o;
  CLI::App app(what, program);
  use_hcosim_help(app);
  app.add_option("--name", o.name, "service name, the key of its ServiceStatus (1 to 31 characters)")
      ->option_text("NAME")
      ->required()
      ->check(CLI::Validator(
          [](std::string& s) { return s.empty() || s.size() > 31 ? "needs 1 to 31 characters" : ""; }, ""));
  app.add_option("--rate", o.rate_hz, "step rate, Hz")->option_text("HZ")->required()->check(within(1e-6, 1e5));
  // No $HCOSIM_DOMAIN here, unlike the tools: a service is on the domain it is given.
  app.add_option("--domain", o.domain, "DDS domain id (default 0)")
      ->option_text("D")
      ->check(CLI::Range(0, adapters::kMaxDomain));
  app.add_option_function<std::string>(
         "--mode", [&](const std::string& m) { o.mode = adapters::parse_mode(m); },
         "time: wall clock, or the lockstep clock's ticks")
      ->option_text("realtime|lockstep")
      ->check(CLI::IsMember({"realtime", "lockstep"}).description(""));
  app.add_option("--step", o.step_s, "base step, s (default 1/rate)")->option_text("S")->check(within(1e-9, 1e3));
  app.add_option("--duration", o.duration_s, "run time, s; 0: until stopped (real time only)")
      ->option_text("S")
      ->check(within(0, 1e9));
  app.add_option("--qos", o.qos_file, "Fast DDS XML profiles (default: the tree's deploy/qos.xml)")
      ->option_text("FILE");
  app.add_option("--deployment", o.deployment, "deployment file holding this service's params")->option_text("FILE");
  app.add_option("--host", o.host, "its host in the deployment's hosts: the network it joins (docs/deployment.md)")
      ->option_text("NAME");
  app.add_option("--out", o.out, "folder for the files the service writes")->option_text("DIR");
  app.add_option("--priority", o.scheduling.priority, "SCHED_FIFO priority 1..99 (0: normal scheduling)")
      ->option_text("P")
      ->check(CLI::Range(0, 99));
  app.add_option("--cpu", o.scheduling.cpu, "pin to this CPU (-1: any)")->option_text("N")->check(CLI::Range(-1, 1023));
  return run_command_line(app, argc, argv, [&] {
    if (o.step_s == 0) o.step_s = 1.0 / o.rate_hz;
    if (o.qos_file.empty()) o.qos_file = default_qos_file();
    return run(o);
  });
}

Service::Service(Options options)
    : options_(std::move(options)),
      period_steps_(steps_per_period(options_)),
      deployment_(options_.deployment.empty() ? adapters::Deployment{}
                                              : adapters::load_deployment(options_.deployment)),
      scheduling_(schedule(options_)),
      participant_(options_.domain, options_.name, options_.qos_file, &recordings_,
                   options_.mode == adapters::Mode::kLockstep, Security{deployment_.security, options_.name},
                   network_of(deployment_, options_.host)),
      params_(params_of(deployment_, options_.name)),
      status_(participant_) {
  install_stop_handlers();
  watch_stop(options_.name);
  std::printf("%s: scheduling: %s\n", options_.name.c_str(), scheduling_.c_str());
  std::fflush(stdout);
  heartbeat(0, 0, Phase::kStarting);
}

StepStamp Service::stamp(const Tick& tick) const {
  StepStamp s;
  s.step(tick.step);
  s.sim_time_ns(tick.sim_time_ns);
  s.wall_time_ns(wall_ns());
  return s;
}

void Service::record_step(double jitter_us, double step_us, bool overrun) {
  ++steps_;
  if (overrun) ++overruns_;
  jitter_us_.add(jitter_us);
  step_us_.add(step_us);
}

void Service::heartbeat(std::int64_t sim_time_ns, std::uint64_t step, Phase phase) {
  const std::int64_t now = mono_ns();
  const std::int64_t since = now - last_heartbeat_ns_;
  if (phase == phase_ && last_heartbeat_ns_ != 0 && since < kHeartbeatNs) return;

  ServiceStatus s;
  s.service(options_.name);
  s.stamp().step(step);
  s.stamp().sim_time_ns(sim_time_ns);
  s.stamp().wall_time_ns(wall_ns());
  s.pid(static_cast<std::uint32_t>(getpid()));
  s.mode(to_string(options_.mode));
  s.state(phase == Phase::kStarting ? "starting" : phase == Phase::kRunning ? "running" : "stopping");
  s.rate_target_hz(options_.rate_hz);
  // The first report of the loop follows the start-up report by one step
  // (or by the model's build): no period to measure a rate over yet.
  const bool measured = phase_ != Phase::kStarting && since > 0;
  s.rate_achieved_hz(measured ? double(steps_ - steps_at_heartbeat_) * 1e9 / double(since) : 0.0);
  s.jitter_p50_us(jitter_us_.percentile(0.5));
  s.jitter_p99_us(jitter_us_.percentile(0.99));
  s.step_p99_us(step_us_.percentile(0.99));
  s.steps(steps_);
  s.overruns(overruns_);
  {
    std::lock_guard<std::mutex> l(rejections_.m);
    s.samples_rejected(rejections_.count);
    s.last_rejection(rejections_.last.substr(0, 128));
  }
  s.outputs_skipped(outputs_skipped_);
  s.outputs_shed(outputs_shed_);
  s.scheduling(scheduling_.substr(0, 127));
  s.in_tick_ratio(in_tick_ratio_);
  s.force_error_p99_n(force_error_p99_n_);
  status_.write(s);

  jitter_us_.clear();
  step_us_.clear();
  steps_at_heartbeat_ = steps_;
  last_heartbeat_ns_ = now;
  phase_ = phase;
}

int Service::run(const std::function<void(const Tick&)>& step) {
  const int code = options_.mode == adapters::Mode::kLockstep ? run_lockstep(step) : run_realtime(step);
  heartbeat(std::int64_t(steps_ * period_steps_ * options_.step_s * 1e9), steps_ * period_steps_, Phase::kStopping);
  settle();
  return code;
}

void Service::settle() { participant_.publisher()->wait_for_acknowledgments(to_dds(std::chrono::milliseconds(500))); }

int Service::run_realtime(const std::function<void(const Tick&)>& step) {
  const std::int64_t period_ns = std::llround(1e9 / options_.rate_hz);
  const std::int64_t start = mono_ns();
  const std::int64_t end = options_.duration_s > 0 ? start + std::llround(options_.duration_s * 1e9) : INT64_MAX;
  std::int64_t k = 0;
  while (!g_stop && !finished_) {
    const std::int64_t due = start + k * period_ns;
    if (due >= end) break;
    timespec ts{static_cast<time_t>(due / 1'000'000'000), static_cast<long>(due % 1'000'000'000)};
    // Sleep, never spin: on 2 cores a spinning loop starves Fast DDS's own threads.
    if (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) continue;
    const std::int64_t woke = mono_ns();
    const Tick tick{std::uint64_t(std::llround(double(k * period_ns) / (options_.step_s * 1e9))), k * period_ns,
                    period_ns * 1e-9, (woke - due) * 1e-3};
    step(tick);
    const std::int64_t done = mono_ns();
    // A step that ends after the next one was due is an overrun; the missed
    // ticks are skipped, not run late in a burst.
    std::int64_t next = k + 1;
    const bool overrun = done > start + next * period_ns;
    if (overrun) {
      next = (done - start) / period_ns + 1;
      outputs_shed_ += std::uint64_t(next - k - 1);  // the skipped ticks' outputs
    }
    record_step((woke - due) * 1e-3, (done - woke) * 1e-3, overrun);
    heartbeat(tick.sim_time_ns, tick.step);
    k = next;
  }
  return 0;
}

// Waits up to 2 s for `wait(slice)` to say every reader acknowledged, in
// slices so that a stop request (up's SIGTERM once the clock is done) is
// heard at once instead of after the whole wait.
template <class Wait>
bool acknowledged(Wait&& wait) {
  for (int i = 0; i < 40 && !g_stop; ++i)
    if (wait(std::chrono::milliseconds(50))) return true;
  return false;
}

// Before the first step: every hcosim up of the run heard ($HCOSIM_UPS,
// set by up), then every writer reaching each of them that records, so
// that the run's recording holds each writer's samples from step 0.
void Service::wait_for_recordings() {
  const char* env = std::getenv("HCOSIM_UPS");
  const int ups = env ? std::atoi(env) : 0;
  const std::int64_t deadline = mono_ns() + kRecordingWaitNs;
  std::vector<std::string> left;
  const auto ready = [&] {
    if (recordings_.ups() < ups) return false;
    left = unreached(participant_, recordings_.prefixes());
    return left.empty();
  };
  while (!g_stop && !ready() && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (g_stop || ready()) return;
  const long long waited_s = kRecordingWaitNs / 1'000'000'000;
  if (recordings_.ups() < ups) {
    std::cerr << options_.name << ": heard " << recordings_.ups() << " of the run's " << ups << " hcosim up after "
              << waited_s << " s; a recording by another may lack this service's first steps\n";
    return;
  }
  std::string topics;
  for (const std::string& t : left) topics += (topics.empty() ? "" : ", ") + t;
  std::cerr << options_.name << ": the recording has not matched this service's writers of " << topics << " after "
            << waited_s << " s; it may lack their first steps\n";
}

int Service::run_lockstep(const std::function<void(const Tick&)>& step) {
  Reader<ClockTick> ticks(
      participant_, [](const ClockTick& t) { return adapters::validate(t); }, &rejections_);
  Writer<StepDone> done(participant_);
  std::uint64_t expected = 0;
  bool finished = false;
  int code = 0;
  std::int64_t sim_ns = 0;
  std::int64_t last_tick_ns = 0;  // 0: before tick 0, which waits for the clock to start
  while (!g_stop && !finished && code == 0) {
    heartbeat(sim_ns, expected);
    if (last_tick_ns > 0 && mono_ns() - last_tick_ns > kTickWaitNs) {
      std::cerr << options_.name << ": no tick from the clock for " << kTickWaitNs / 1'000'000'000 << " s after step "
                << expected - 1 << "; the clock stopped or its host is gone\n";
      return 1;
    }
    if (!ticks.wait(std::chrono::milliseconds(100))) continue;
    ticks.take([&](const ClockTick& t) {
      if (finished || code != 0) return;
      if (t.step() != expected) {
        std::cerr << options_.name << ": lockstep tick " << t.step() << " arrived, expected " << expected << "\n";
        code = 1;
        return;
      }
      if (t.step() == 0) wait_for_recordings();
      const std::int64_t t0 = mono_ns();
      sim_ns = t.sim_time_ns();
      if (t.step() % period_steps_ == 0) {
        step(Tick{t.step(), t.sim_time_ns(), double(period_steps_) * double(t.step_ns()) * 1e-9});
        record_step(0.0, (mono_ns() - t0) * 1e-3, false);
      }
      // The clock matches this writer from its reader's side before it
      // sends tick 0, but this writer may not have matched that reader
      // yet: a VOLATILE sample written then is lost and the clock waits
      // forever (seen in CI). Wait for this side's match first, with the
      // clock itself: a recorder's reader of StepDone matched earlier
      // (`hcosim up --record`) is not it (integration.haptic_loop stuck at
      // step 0 once in eight runs when any match was taken for it).
      const auto clock = ticks.current_writer();
      for (int i = 0; i < 5000 && !done.reaches(clock) && !g_stop; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      // This step's outputs reach every reader before the clock hears the
      // step is done, so the next step's inputs are all there.
      if (!acknowledged([&](auto d) {
            return participant_.publisher()->wait_for_acknowledgments(to_dds(d)) == ReturnCode_t::RETCODE_OK;
          }) &&
          !g_stop)
        std::cerr << options_.name << ": step " << t.step() << ": outputs not acknowledged by every reader in 2 s\n";
      StepDone d;
      d.service(options_.name);
      d.step(t.step());
      if (!done.write(d)) {
        std::cerr << options_.name << ": could not write StepDone for step " << t.step() << "\n";
        code = 1;
        return;
      }
      ++expected;
      last_tick_ns = mono_ns();
      finished = t.last();
    });
  }
  if (finished && !acknowledged([&](auto d) { return done.wait_acknowledged(d); }) && !g_stop)
    std::cerr << options_.name << ": the clock did not acknowledge the last StepDone\n";
  return code;
}

int guarded_main(const char* program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const adapters::ConfigError& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace hcosim::services::runtime
