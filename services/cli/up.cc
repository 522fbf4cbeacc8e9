// hcosim up: start a deployment's services as processes, watch them, stop them.
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>
#include <csignal>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "services/cli/cli.h"
#include "services/runtime/recording.h"
#include "services/runtime/service.h"

namespace fs = std::filesystem;

namespace hcosim::services::cli {
namespace {

volatile std::sig_atomic_t g_signal = 0;
void on_signal(int s) { g_signal = s; }

constexpr double kStopGraceS = 2.0;
// Participant ids of restarted services: from here to runtime::kMaxParticipantId,
// above those Fast DDS gives the first participants of a host (0, 1, ...),
// taken in turn and again from the start when used up.
constexpr int kRestartIds = 60;
constexpr double kJoinWaitS = 10.0;    // s before up names the services that have not joined
constexpr double kStartWaitS = 120.0;  // s the duration waits for every service's loop to run

struct Child {
  std::string name;
  std::string exe;
  std::vector<std::string> args;
  runtime::OnFailure policy = runtime::OnFailure::kStopAll;
  pid_t pid = -1;
  int status = 0;  // waitpid status once reaped
  bool reaped = false;
  int restarts = 0;
  std::string env = "";  // one NAME=VALUE added to its environment ("" none)
};

// build/bin/hcosim_<kind>, searched in $HCOSIM_SERVICE_PATH, then beside this program.
std::string find_service(const std::string& kind, const std::string& file, int line) {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("HCOSIM_SERVICE_PATH")) {
    std::stringstream ss(env);
    for (std::string d; std::getline(ss, d, ':');)
      if (!d.empty()) dirs.emplace_back(d);
  }
  dirs.push_back(fs::read_symlink("/proc/self/exe").parent_path());
  for (const auto& d : dirs) {
    const fs::path p = d / ("hcosim_" + kind);
    if (access(p.c_str(), X_OK) == 0) return p.string();
  }
  std::string known;
  for (const auto& d : dirs) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(d, ec)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("hcosim_", 0) == 0 && n != "hcosim_clock") known += (known.empty() ? "" : ", ") + n.substr(7);
    }
  }
  throw adapters::ConfigError(file + ":" + std::to_string(line) + ":1: no service of kind '" + kind +
                              "' (known kinds: " + (known.empty() ? "none" : known) + ")");
}

std::string describe(int status) {
  if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status))
    return std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) +
           ")";
  return "status " + std::to_string(status);
}

bool failed(const Child& c) { return !WIFEXITED(c.status) || WEXITSTATUS(c.status) != 0; }

// The last line a service wrote to its log: its error, when it failed.
std::string last_line(const fs::path& log) {
  std::ifstream in(log, std::ios::binary | std::ios::ate);
  if (!in) return "";
  const std::streamoff size = in.tellg(), from = std::max<std::streamoff>(0, size - 4096);
  std::string tail(std::size_t(size - from), '\0');
  in.seekg(from);
  in.read(tail.data(), std::streamsize(tail.size()));
  std::istringstream lines(tail);
  std::string line, last;
  while (std::getline(lines, line))
    if (!line.empty() && line.rfind("--- hcosim up:", 0) != 0) last = line;
  return last;
}

// Starts c with its output in `log`, appended to for a restart so that the
// failed run's output is kept. A restart forks while DDS threads run, so
// the child calls only async-signal-safe functions before exec: everything
// it needs is built before the fork.
pid_t spawn(const Child& c, const fs::path& log, bool append = false) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(c.exe.c_str()));
  for (const auto& a : c.args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::vector<char*> envp;
  for (char** e = environ; *e; ++e) envp.push_back(*e);
  if (!c.env.empty()) envp.push_back(const_cast<char*>(c.env.c_str()));
  envp.push_back(nullptr);
  const std::string failed = "hcosim up: cannot exec " + c.exe + "\n";
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid > 0) return pid;
  // Child: die with the launcher, even if it is killed with SIGKILL.
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() == 1) _exit(127);
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | (append ? O_APPEND : O_TRUNC), 0644);
  if (fd >= 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    close(fd);
  }
  // up's own DDS sockets and segments must not live on in the service:
  // a copy of a socket would take datagrams meant for up.
  syscall(SYS_close_range, 3u, ~0u, 0u);
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  execve(c.exe.c_str(), argv.data(), envp.data());
  if (write(STDERR_FILENO, failed.data(), failed.size()) < 0) _exit(127);
  _exit(127);
}

// Reaps exited children without blocking; returns the newly exited ones.
std::vector<Child*> reap(std::vector<Child>& children) {
  std::vector<Child*> exited;
  for (auto& c : children) {
    if (c.reaped) continue;
    if (waitpid(c.pid, &c.status, WNOHANG) == c.pid) {
      c.reaped = true;
      exited.push_back(&c);
    }
  }
  return exited;
}

bool all_reaped(const std::vector<Child>& children) {
  for (const auto& c : children)
    if (!c.reaped) return false;
  return true;
}

// SIGTERM to every running child, SIGKILL after the grace period. Returns
// true if some child had to be killed.
bool stop_all(std::vector<Child>& children) {
  for (auto& c : children)
    if (!c.reaped) kill(c.pid, SIGTERM);
  const std::int64_t deadline = runtime::mono_ns() + std::int64_t(kStopGraceS * 1e9);
  while (!all_reaped(children) && runtime::mono_ns() < deadline) {
    reap(children);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  bool killed = false;
  for (auto& c : children) {
    if (c.reaped) continue;
    std::cerr << "hcosim up: " << c.name << " (pid " << c.pid << ") ignored SIGTERM for " << kStopGraceS
              << " s; killing it\n";
    kill(c.pid, SIGKILL);
    waitpid(c.pid, &c.status, 0);
    c.reaped = true;
    killed = true;
  }
  return killed;
}

// The run's progress from every service's ServiceStatus, as one line:
// simulated time, real-time factor, and each service's achieved rate and
// overruns. On a terminal the line is rewritten in place; in a log, a new
// line every kLogProgressS. Also which services have left "starting".
class Progress {
 public:
  explicit Progress(runtime::Participant& p)
      : status_(p, [](const ServiceStatus& s) { return adapters::validate(s); }), tty_(isatty(STDOUT_FILENO)) {}

  void update() {
    status_.take([&](const ServiceStatus& s) {
      ServiceStatus& last = latest_[s.service().to_string()];
      // The pace from two reports of one service, by their own stamps.
      const double wall = (s.stamp().wall_time_ns() - last.stamp().wall_time_ns()) * 1e-9;
      if (last.steps() > 0 && wall > 0 && s.stamp().sim_time_ns() >= sim_ns_) {
        factor_ = (s.stamp().sim_time_ns() - last.stamp().sim_time_ns()) * 1e-9 / wall;
        sim_ns_ = s.stamp().sim_time_ns();
      }
      const bool first = last.service().size() == 0;
      last = s;
      if (s.state().to_string() != "starting") ran_.insert(s.service().to_string());
      // What each service got of its scheduling, once (docs/haptic.md).
      if (first) {
        if (tty_ && shown_) std::printf("\n"), shown_ = false;
        std::printf("  %-16s scheduling: %s\n", s.service().c_str(), s.scheduling().c_str());
      }
    });
    const std::int64_t now = runtime::mono_ns();
    if (now - printed_ns_ < (tty_ ? 500'000'000 : std::int64_t(kLogProgressS * 1e9)) || sim_ns_ == 0) return;
    printed_ns_ = now;
    std::string line = text("sim %.1f s, real-time factor %.2f", sim_ns_ * 1e-9, factor_);
    for (const auto& [name, s] : latest_)
      line +=
          text(" | %s %.0f Hz, %llu overruns%s", name.c_str(), s.rate_achieved_hz(),
               static_cast<unsigned long long>(s.overruns()),
               s.outputs_shed() ? text(", %llu shed", static_cast<unsigned long long>(s.outputs_shed())).c_str() : "");
    std::printf(tty_ ? "\r%s\033[K" : "%s\n", line.c_str());
    std::fflush(stdout);
    shown_ = true;
  }
  // Whether `name` has reported that its loop runs (or has run).
  bool running(const std::string& name) const { return ran_.count(name) > 0; }
  // Ends the in-place line before other output.
  void finish() {
    if (tty_ && shown_) std::printf("\n");
    shown_ = false;
  }

 private:
  static constexpr double kLogProgressS = 5;
  template <class... A>
  static std::string text(const char* f, A... a) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a...);
    return buf;
  }
  runtime::Reader<ServiceStatus> status_;
  std::map<std::string, ServiceStatus> latest_;
  std::set<std::string> ran_;
  std::int64_t sim_ns_ = 0, printed_ns_ = 0;  // the furthest service's simulated time
  double factor_ = 0;                         // simulated over wall time between its last two reports
  bool tty_, shown_ = false;
};

// The participants discovered on the domain, by name: a service's
// participant carries the service's name.
class Joined : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    std::lock_guard<std::mutex> l(m_);
    names_.insert(info.info.m_participantName.to_string());
  }
  bool has(const std::string& name) {
    std::lock_guard<std::mutex> l(m_);
    return names_.count(name) > 0;
  }

 private:
  std::mutex m_;
  std::set<std::string> names_;
};

// A process that died without closing its participant leaves shared-memory
// segments behind; Fast DDS's tool removes the ones nobody uses.
// It misses one kind: Fast DDS 2.9 removes a port's segment when the last
// process that opened it closes it, and a killed process never closes, so
// every port it wrote to outlives its listener, without the lock file
// (fastrtps_portN_el) by which the tool finds zombies. Once the run is over,
// the domain's unicast ports (7400 + 250 * domain + 10 + 2 * id, + 1) that nobody
// listens on go too, as the tool would treat them if it saw them.
void clean_shared_memory(int domain) {
  if (std::system("fastdds shm clean > /dev/null 2>&1") != 0)
    std::cerr << "hcosim up: 'fastdds shm clean' failed; stale segments may remain in /dev/shm\n";
  const fs::path shm = "/dev/shm";
  const int first = 7400 + 250 * domain + 10;
  for (int port = first; port < first + 2 * (runtime::kMaxParticipantId + 1); ++port) {
    const std::string name = "fastrtps_port" + std::to_string(port);
    std::error_code ec;
    if (!fs::exists(shm / name, ec) || fs::exists(shm / (name + "_el"), ec) || fs::exists(shm / (name + "_sl"), ec))
      continue;
    fs::remove(shm / name, ec);
    fs::remove(shm / ("sem." + name + "_mutex"), ec);
  }
}

}  // namespace

int up(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--duration", "--mode", "--out", "--record"}, {});
  const std::string record = a.get("--record", "");
  if (a.positional.size() != 1) throw std::invalid_argument("up needs exactly one deployment FILE");
  runtime::Deployment d = runtime::load_deployment(a.positional[0]);
  if (a.has("--mode")) d.mode = runtime::parse_mode(a.get("--mode", ""));
  d.duration_s = a.number("--duration", d.duration_s);
  if (d.duration_s < 0) throw std::invalid_argument("--duration must not be negative");
  if (d.mode == runtime::Mode::kLockstep && d.duration_s == 0)
    throw std::invalid_argument("lockstep needs a duration (in the file or --duration)");
  const fs::path out = a.get("--out", "out");
  const fs::path logs = out / "logs";
  fs::create_directories(logs);

  const std::string file = fs::absolute(d.file).string();
  auto common = [&](const std::string& name, double rate) {
    std::ostringstream r, s;
    r.precision(17);
    s.precision(17);
    r << rate;
    s << d.step_s;
    return std::vector<std::string>{"--name",       name,
                                    "--domain",     std::to_string(d.domain),
                                    "--mode",       runtime::to_string(d.mode),
                                    "--rate",       r.str(),
                                    "--step",       s.str(),
                                    "--deployment", file,
                                    "--out",        fs::absolute(out).string()};
  };
  const auto scheduling = [](const runtime::ServiceSpec& s) {
    return std::vector<std::string>{"--priority", std::to_string(s.priority), "--cpu", std::to_string(s.cpu)};
  };
  std::vector<Child> children;
  for (const auto& s : d.services) {
    if (!s.unneeded.empty()) {
      std::printf("hcosim up: not starting %s: %s\n", s.name.c_str(), s.unneeded.c_str());
      continue;
    }
    runtime::check_policy(s, d.mode);  // --mode may have changed the file's mode
    Child c{s.name, find_service(s.kind, d.file, s.line), common(s.name, s.rate_hz), s.on_failure};
    const auto sch = scheduling(s);
    c.args.insert(c.args.end(), sch.begin(), sch.end());
    children.push_back(std::move(c));
  }
  // The clock alone would step nothing: surely a mistake in the file.
  if (children.empty())
    throw adapters::ConfigError(d.services_where + ": nothing to run: " +
                                (d.services.empty() ? std::string("the deployment lists no services")
                                                    : "the scene needs none of its services (above)"));
  if (d.mode == runtime::Mode::kLockstep) {
    Child clock{"clock", find_service("clock", d.file, 1), common("clock", 1.0 / d.step_s)};
    std::ostringstream dur;
    dur.precision(17);
    dur << d.duration_s;
    clock.args.insert(clock.args.end(), {"--duration", dur.str()});
    children.push_back(std::move(clock));
  }

  // Every process's credentials, before any starts (docs/security.md).
  const runtime::Security security{d.security, runtime::kToolIdentity};
  if (security.on()) try {
      runtime::check_credentials(security);
      for (const auto& c : children) runtime::check_credentials({d.security, c.name});
    } catch (const std::runtime_error& e) {
      throw adapters::ConfigError(d.security_where + ": " + e.what());
    }

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  std::printf("hcosim up: %s, domain %d, %s, %zu service(s)%s%s\n", d.file.c_str(), d.domain,
              runtime::to_string(d.mode), children.size(), d.duration_s > 0 ? "" : ", until Ctrl-C",
              security.on() ? (", DDS Security on (" + d.security + ")").c_str() : "");
  // up's participant exists before the services, so that the recorder's
  // readers are there when their writers appear.
  Joined joined;
  // Owned, so that it is gone before the shared-memory clean at the end:
  // a dead process's ports that it holds open would stay behind.
  auto participant = std::make_unique<runtime::Participant>(d.domain, "hcosim_up", runtime::default_qos_file(), &joined,
                                                            false, security);
  // In lockstep the recorder's readers are reliable: the services wait for
  // them too, so a recording holds every sample.
  participant->set_lockstep(d.mode == runtime::Mode::kLockstep);
  auto progress = std::make_unique<Progress>(*participant);
  std::unique_ptr<runtime::Recorder> recorder;
  if (!record.empty()) recorder = std::make_unique<runtime::Recorder>(*participant, record, std::vector<std::string>{});
  for (auto& c : children) {
    c.pid = spawn(c, logs / (c.name + ".log"));
    std::printf("  started %-16s pid %-7d %s\n", c.name.c_str(), int(c.pid), c.exe.c_str());
  }
  std::fflush(stdout);

  // Watch: a child that exits ends the run (lockstep: the clock exiting 0
  // is the normal end) unless its on_failure policy says otherwise; so do
  // the duration and Ctrl-C.
  const std::int64_t start = runtime::mono_ns();
  // A real-time run's duration counts from when every service runs its
  // loop (one may first build its model for seconds), or from kStartWaitS
  // if one never says so; lockstep runs end with the clock.
  const bool timed = d.mode == runtime::Mode::kRealtime && d.duration_s > 0;
  std::int64_t end = INT64_MAX;
  std::string reason;
  int code = 0;
  bool crashed = false;    // some process died by a signal: its shared memory stays behind
  std::string last_words;  // failed services' last log lines, not yet printed
  const Child shm_clean{"shm_clean", "/bin/sh", {"-c", "fastdds shm clean"}};
  pid_t cleaner = -1;  // a running shm_clean, or -1
  int next_id = 0;     // restarts so far, for participant ids
  // Say when every service's participant has been discovered, or after
  // kJoinWaitS which have not; then when every service runs, or which
  // still start.
  bool all_joined = false, join_warned = false, all_running = false, start_warned = false;
  while (reason.empty()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    progress->update();
    const double waited = (runtime::mono_ns() - start) * 1e-9;
    if (!all_joined) {
      std::string missing;
      for (const auto& c : children)
        if (!joined.has(c.name)) missing += (missing.empty() ? "" : ", ") + c.name;
      if (missing.empty()) {
        all_joined = true;
        progress->finish();
        std::printf("hcosim up: every service joined domain %d in %.2f s\n", d.domain, waited);
        std::fflush(stdout);
      } else if (!join_warned && waited > kJoinWaitS) {
        join_warned = true;
        progress->finish();
        std::printf("hcosim up: after %.0f s still no status from: %s\n", kJoinWaitS, missing.c_str());
        std::fflush(stdout);
      }
    }
    if (!all_running) {
      std::string starting;
      for (const auto& c : children)
        if (!progress->running(c.name)) starting += (starting.empty() ? "" : ", ") + c.name;
      if (starting.empty() || waited > kStartWaitS) {
        all_running = true;
        if (timed) end = runtime::mono_ns() + std::int64_t(d.duration_s * 1e9);
        progress->finish();
        if (starting.empty())
          std::printf("hcosim up: every service running after %.2f s\n", waited);
        else
          std::printf("hcosim up: after %.0f s still starting: %s; the run goes on without waiting\n", kStartWaitS,
                      starting.c_str());
        std::fflush(stdout);
      } else if (!start_warned && all_joined && waited > kJoinWaitS) {
        start_warned = true;
        progress->finish();
        std::printf("hcosim up: still starting after %.0f s: %s\n", kJoinWaitS, starting.c_str());
        std::fflush(stdout);
      }
    }
    if (cleaner > 0 && waitpid(cleaner, nullptr, WNOHANG) == cleaner) cleaner = -1;
    if (g_signal)
      reason = std::string("stopped by ") + (g_signal == SIGINT ? "SIGINT" : "SIGTERM");
    else if (runtime::mono_ns() >= end)
      reason = "duration reached";
    else
      for (Child* c : reap(children)) {
        if (!reason.empty()) break;
        // Exit status 2 is a refused configuration or argument
        // (runtime::guarded_main); before the loop ever ran, a restart would be
        // refused the same way.
        const bool refused = WIFEXITED(c->status) && WEXITSTATUS(c->status) == 2 && !progress->running(c->name);
        // A process killed from outside (SIGKILL, SIGTERM) wrote no last word.
        const int sig = WIFSIGNALED(c->status) ? WTERMSIG(c->status) : 0;
        const bool killed = sig == SIGKILL || sig == SIGTERM;
        if (failed(*c) && !killed)
          if (const std::string l = last_line(logs / (c->name + ".log")); !l.empty())
            last_words += "  " + c->name + ": " + l + "\n";
        if (failed(*c) && c->policy == runtime::OnFailure::kRestart && c->restarts < runtime::kMaxRestarts &&
            !refused) {
          ++c->restarts;
          crashed = crashed || WIFSIGNALED(c->status);
          progress->finish();
          std::printf("hcosim up: service '%s' ended (%s); restarting it (%d of %d)\n%s", c->name.c_str(),
                      describe(c->status).c_str(), c->restarts, runtime::kMaxRestarts, last_words.c_str());
          last_words.clear();
          std::fflush(stdout);
          const fs::path log = logs / (c->name + ".log");
          if (FILE* f = std::fopen(log.c_str(), "a")) {
            std::fprintf(f, "--- hcosim up: ended (%s), restart %d ---\n", describe(c->status).c_str(), c->restarts);
            std::fclose(f);
          }
          // A participant id of its own: with the dead process's id it
          // would reuse its shared-memory ports, which the others keep
          // pushing to until Fast DDS finds them dead (seconds).
          c->env = "HCOSIM_PARTICIPANT_ID=" +
                   std::to_string(kRestartIds + next_id++ % (runtime::kMaxParticipantId + 1 - kRestartIds));
          c->pid = spawn(*c, log, true);
          c->reaped = false;
          // The killed process's segments go now, not at the end of a run
          // that may last hours; in the background, so the recorder keeps
          // polling (the tool removes only segments nobody holds).
          if (WIFSIGNALED(c->status) && cleaner < 0) cleaner = spawn(shm_clean, logs / "shm_clean.log", true);
        } else if (failed(*c) && c->policy == runtime::OnFailure::kIgnore) {
          progress->finish();
          std::printf("hcosim up: service '%s' ended (%s); on_failure: ignore, the others run on\n%s", c->name.c_str(),
                      describe(c->status).c_str(), last_words.c_str());
          last_words.clear();
          std::fflush(stdout);
          code = 1;
          if (all_reaped(children)) reason = "every service ended";
        } else if (failed(*c)) {
          const bool unrestarted = refused && c->policy == runtime::OnFailure::kRestart;
          reason = "service '" + c->name + "' ended (" + describe(c->status) +
                   (unrestarted ? " before its loop ran; a refused configuration is not restarted" : "") + ")" +
                   (c->restarts ? " after " + std::to_string(c->restarts) + " restarts" : "");
          code = 1;
        } else if (d.mode == runtime::Mode::kRealtime) {
          reason = "service '" + c->name + "' finished";
        } else if (c->name == "clock") {
          // Followers exit by themselves after the last tick.
          reason = "lockstep run complete";
          const std::int64_t deadline = runtime::mono_ns() + std::int64_t(kStopGraceS * 1e9);
          while (!all_reaped(children) && runtime::mono_ns() < deadline) {
            reap(children);
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
          }
        }
        // A lockstep follower that exits 0 has seen the last tick; the clock ends the run.
      }
  }
  progress->finish();
  crashed = stop_all(children) || crashed;
  if (recorder) {
    recorder->close();
    std::printf("hcosim up: recorded %llu samples to %s\n", static_cast<unsigned long long>(recorder->samples()),
                record.c_str());
    if (const std::string lost = recorder->losses(); !lost.empty())
      std::printf("hcosim up: samples Fast DDS reports the recording never received: %s\n", lost.c_str());
  }
  for (const auto& c : children) {
    // SIGTERM from us is a clean stop; anything else non-zero is a failure.
    const bool ours = WIFSIGNALED(c.status) && WTERMSIG(c.status) == SIGTERM;
    if (failed(c) && !ours) {
      code = 1;
      crashed = crashed || WIFSIGNALED(c.status);
    }
  }
  if (cleaner > 0) waitpid(cleaner, nullptr, 0);
  recorder.reset();
  progress.reset();
  participant.reset();
  if (crashed) clean_shared_memory(d.domain);

  std::printf("hcosim up: %s after %.1f s\n%s", reason.c_str(), (runtime::mono_ns() - start) * 1e-9,
              last_words.c_str());
  for (const auto& c : children)
    std::printf("  %-16s %-32s log %s\n", c.name.c_str(),
                (describe(c.status) + (c.restarts ? ", " + std::to_string(c.restarts) + " restarts" : "")).c_str(),
                (logs / (c.name + ".log")).c_str());
  std::printf("outputs: %s\n", fs::absolute(out).c_str());
  return code;
}

}  // namespace hcosim::services::cli
