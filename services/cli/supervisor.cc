#include "services/cli/supervisor.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>
#include <utility>

#include "services/runtime/participant.h"
#include "services/runtime/service.h"

namespace fs = std::filesystem;

namespace hcosim::services::cli {
namespace {

// Participant ids of restarted services: from here to runtime::kMaxParticipantId,
// above those Fast DDS gives the first participants of a host (0, 1, ...),
// taken in turn and again from the start when used up.
constexpr int kRestartIds = 60;

bool failed(const Child& c) { return !WIFEXITED(c.status) || WEXITSTATUS(c.status) != 0; }

// Starts c with its output in `log`, appended to for a restart so that the
// failed run's output is kept. A restart forks while DDS threads run, so
// the child calls only async-signal-safe functions before exec: everything
// it needs is built before the fork.
pid_t spawn(const Child& c, const fs::path& log, bool append) {
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
  const int first = runtime::first_port(domain) + 10;
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

std::string find_program(const std::string& name, const std::string& what) {
  std::stringstream path(std::getenv("PATH") ? std::getenv("PATH") : "/usr/bin:/bin");
  for (std::string d; std::getline(path, d, ':');)
    if (!d.empty() && access((fs::path(d) / name).c_str(), X_OK) == 0) return (fs::path(d) / name).string();
  throw std::runtime_error("no " + name + " in PATH: it is " + what);
}

std::string describe(int status) {
  if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status))
    return std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) +
           ")";
  return "status " + std::to_string(status);
}

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

Supervisor::Supervisor(fs::path logs, adapters::Mode mode) : logs_(std::move(logs)), mode_(mode) {}

Supervisor::~Supervisor() { stop(); }

pid_t Supervisor::start(Child c) {
  c.pid = spawn(c, log_of(c.name), false);
  c.reaped = false;
  children_.push_back(std::move(c));
  return children_.back().pid;
}

std::vector<Child*> Supervisor::reap() {
  std::vector<Child*> exited;
  for (auto& c : children_) {
    if (c.reaped) continue;
    if (waitpid(c.pid, &c.status, WNOHANG) == c.pid) {
      c.reaped = true;
      exited.push_back(&c);
    }
  }
  return exited;
}

bool Supervisor::all_reaped() const {
  for (const auto& c : children_)
    if (!c.reaped) return false;
  return true;
}

void Supervisor::restart(Child& c) {
  ++c.restarts;
  crashed_ = crashed_ || WIFSIGNALED(c.status);
  const fs::path log = log_of(c.name);
  if (FILE* f = std::fopen(log.c_str(), "a")) {
    std::fprintf(f, "--- hcosim up: ended (%s), restart %d ---\n", describe(c.status).c_str(), c.restarts);
    std::fclose(f);
  }
  // A participant id of its own: with the dead process's id it would
  // reuse its shared-memory ports, which the others keep pushing to until
  // Fast DDS finds them dead (seconds).
  c.env = "HCOSIM_PARTICIPANT_ID=" +
          std::to_string(kRestartIds + next_id_++ % (runtime::kMaxParticipantId + 1 - kRestartIds));
  c.pid = spawn(c, log, true);
  c.reaped = false;
  // The killed process's segments go now, not at the end of a run that
  // may last hours; in the background, so that up keeps polling (the tool
  // removes only segments nobody holds).
  if (WIFSIGNALED(c.status) && cleaner_ < 0)
    cleaner_ = spawn(Child{"shm_clean", "/bin/sh", {"-c", "fastdds shm clean"}}, logs_ / "shm_clean.log", true);
}

std::string Supervisor::poll(const std::function<bool(const std::string&)>& ran, std::string& said) {
  if (cleaner_ > 0 && waitpid(cleaner_, nullptr, WNOHANG) == cleaner_) cleaner_ = -1;
  for (Child* c : reap()) {
    // Exit status 2 is a refused configuration or argument
    // (runtime::guarded_main); before the loop ever ran, a restart would be
    // refused the same way.
    const bool refused = WIFEXITED(c->status) && WEXITSTATUS(c->status) == 2 && !ran(c->name);
    // A process killed from outside (SIGKILL, SIGTERM) wrote no last word.
    const int sig = WIFSIGNALED(c->status) ? WTERMSIG(c->status) : 0;
    const bool killed = sig == SIGKILL || sig == SIGTERM;
    if (failed(*c) && !killed)
      if (const std::string l = last_line(log_of(c->name)); !l.empty()) last_words_ += "  " + c->name + ": " + l + "\n";
    if (failed(*c) && c->policy == adapters::OnFailure::kRestart && c->restarts < adapters::kMaxRestarts && !refused) {
      restart(*c);
      said += "hcosim up: service '" + c->name + "' ended (" + describe(c->status) + "); restarting it (" +
              std::to_string(c->restarts) + " of " + std::to_string(adapters::kMaxRestarts) + ")\n" + last_words();
    } else if (failed(*c) && c->policy == adapters::OnFailure::kIgnore) {
      failed_ = true;
      said += "hcosim up: service '" + c->name + "' ended (" + describe(c->status) +
              "); on_failure: ignore, the others run on\n" + last_words();
      if (all_reaped()) return "every service ended";
    } else if (failed(*c)) {
      const bool unrestarted = refused && c->policy == adapters::OnFailure::kRestart;
      return "service '" + c->name + "' ended (" + describe(c->status) +
             (unrestarted ? " before its loop ran; a refused configuration is not restarted" : "") + ")" +
             (c->restarts ? " after " + std::to_string(c->restarts) + " restarts" : "");
    } else if (mode_ == adapters::Mode::kRealtime) {
      return "service '" + c->name + "' finished";
    } else if (c->name == "clock") {
      // Followers exit by themselves after the last tick; observers are stopped.
      const auto followers_reaped = [&] {
        for (const Child& f : children_)
          if (!f.reaped && !f.observer) return false;
        return true;
      };
      const std::int64_t deadline = runtime::mono_ns() + std::int64_t(kStopGraceS * 1e9);
      while (!followers_reaped() && runtime::mono_ns() < deadline) {
        reap();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
      return "lockstep run complete";
    }
    // A lockstep follower that exits 0 has seen the last tick; the clock
    // ends the run, or on a host the clock is not on (hcosim up --host),
    // the last of its followers.
    bool clock_here = false, followers_done = true;
    for (const Child& f : children_) {
      clock_here = clock_here || f.name == "clock";
      followers_done = followers_done && (f.reaped || f.observer);
    }
    if (!clock_here && followers_done) return "lockstep run complete (the clock runs on another host)";
  }
  return "";
}

void Supervisor::stop() {
  for (auto& c : children_)
    if (!c.reaped) kill(c.pid, SIGTERM);
  const std::int64_t deadline = runtime::mono_ns() + std::int64_t(kStopGraceS * 1e9);
  while (!all_reaped() && runtime::mono_ns() < deadline) {
    reap();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (auto& c : children_) {
    if (c.reaped) continue;
    std::cerr << "hcosim up: " << c.name << " (pid " << c.pid << ") ignored SIGTERM for " << kStopGraceS
              << " s; killing it\n";
    kill(c.pid, SIGKILL);
    waitpid(c.pid, &c.status, 0);
    c.reaped = true;
    crashed_ = true;
  }
  for (const auto& c : children_) crashed_ = crashed_ || (WIFSIGNALED(c.status) && WTERMSIG(c.status) != SIGTERM);
}

void Supervisor::clean(int domain) {
  if (cleaner_ > 0) waitpid(cleaner_, nullptr, 0);
  cleaner_ = -1;
  if (crashed_) clean_shared_memory(domain);
}

int Supervisor::code() const {
  if (failed_) return 1;
  for (const auto& c : children_) {
    // SIGTERM from us is a clean stop; anything else non-zero is a failure.
    const bool ours = WIFSIGNALED(c.status) && WTERMSIG(c.status) == SIGTERM;
    if (failed(c) && !ours) return 1;
  }
  return 0;
}

}  // namespace hcosim::services::cli
