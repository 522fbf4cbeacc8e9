// bench soak: the default deployment (deploy/default.yaml: its scene and
// services) in real time for 30 minutes (30 s with --quick), its virtual
// user's tour played again and again, watched from a participant of the
// bench's own.
//
// window: one row per minute (10 s with --quick): the services' resident
//   memory (rss_mb, the sum of their VmRSS at the window's end), their
//   overruns in the window (from ServiceStatus; haptic_overruns: those of
//   the haptic-rate services, the ones at the haptic priority), the samples Fast DDS
//   reports lost to the bench's readers of the reliable topics
//   (DeformedMesh, RigidBodyState, MarkerPose, ServiceStatus: their
//   SampleLostStatus), and the haptic round trip as the bench sees it:
//   from a HapticState's send (its stamp's wall clock) to the arrival of
//   each ForceFeedback answering it (p50, p99 over the window).
// summary: rss_growth_pct (last window's rss_mb against the first's),
//   reliable_lost (all windows), p99_drift_pct (|last window's p99 - the
//   first's| against the first's), overruns and haptic_overruns (all windows).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include <unordered_map>

#include <yaml-cpp/yaml.h>

#include "services/bench/bench.h"
#include "services/bench/harness.h"
#include "services/runtime/endpoint.h"
#include "services/runtime/service.h"

namespace hcosim::services::bench {
namespace {

namespace fs = std::filesystem;

// kB of resident memory of `pid`, 0 if it is gone.
double rss_kb(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6));
  return 0;
}

// The pids hcosim up reports starting ("  started NAME pid N ...").
std::map<std::string, pid_t> started(const fs::path& log) {
  std::map<std::string, pid_t> out;
  std::ifstream f(log);
  const std::regex re(R"(^\s+started\s+(\S+)\s+pid\s+(\d+))");
  std::smatch m;
  for (std::string line; std::getline(f, line);)
    if (std::regex_search(line, m, re)) out[m[1]] = pid_t(std::stol(m[2]));
  return out;
}

std::string tail(const fs::path& log) {
  std::ifstream f(log);
  std::vector<std::string> lines;
  for (std::string l; std::getline(f, l);) lines.push_back(l);
  std::string out;
  for (std::size_t i = lines.size() > 10 ? lines.size() - 10 : 0; i < lines.size(); ++i) out += lines[i] + "\n";
  return out;
}

std::vector<Row> soak_rows(const Context& c) {
  const double total = c.quick ? 30 : 1800, window = c.quick ? 10 : 60;
  // Absolute: the deployment names the script, read from its own folder.
  const fs::path dir = fs::absolute(c.work / "soak_run");
  fs::create_directories(dir);
  const fs::path file = default_deployment(dir, c.domain, total, 0), log = dir / "up.log";  // the bench stops it
  progress("soak: the default deployment in real time for " + text(total) + " s, a row every " + text(window) + " s (" +
           dir.string() + ")");

  runtime::install_stop_handlers();  // Ctrl-C stops the deployment too, and ends the suite
  runtime::Participant p(c.domain, "bench_soak");
  runtime::Reader<HapticState> states(p);
  runtime::Reader<ForceFeedback> forces(p);
  runtime::Reader<ServiceStatus> status(p);
  runtime::Reader<DeformedMesh> meshes(p);
  runtime::Reader<RigidBodyState> bodies(p);
  runtime::Reader<MarkerPose> poses(p);
  auto lost = [&] { return double(status.lost() + meshes.lost() + bodies.lost() + poses.lost()); };

  const pid_t up = start_up(file, dir / "out", log);
  auto stop = [&] {
    kill(up, SIGINT);
    int st = 0;
    waitpid(up, &st, 0);
    return st;
  };
  // Wait for every service's loop to run (models built) before the first window.
  const std::int64_t start_deadline = runtime::mono_ns() + std::int64_t(60e9);
  while (tail(log).find("every service running") == std::string::npos) {
    if (runtime::mono_ns() > start_deadline || waitpid(up, nullptr, WNOHANG) == up) {
      stop();
      throw std::runtime_error("soak: the deployment did not start:\n" + tail(log));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const std::map<std::string, pid_t> pids = started(log);
  // The haptic-rate services: those whose haptic threads run first.
  std::set<std::string> haptic;
  for (const adapters::ServiceSpec& spec : adapters::load_deployment(file.string()).services)
    if (spec.priority > 0) haptic.insert(spec.name);

  std::unordered_map<std::uint64_t, std::int64_t> sent;  // omni's HapticState seq -> its wall clock, ns
  std::map<std::string, std::uint64_t> overruns;         // latest ServiceStatus.overruns per service
  runtime::Window rtt_us(1 << 20);
  std::vector<Row> rows;
  double lost_before = lost(), overruns_before = 0, haptic_before = 0;
  const std::int64_t start = runtime::mono_ns();
  for (int w = 1; w * window <= total + 1e-9; ++w) {
    const std::int64_t end = start + std::int64_t(w * window * 1e9);
    while (runtime::mono_ns() < end) {
      if (runtime::stop_requested()) {
        stop();
        throw std::runtime_error("soak: stopped by a signal in window " + std::to_string(w));
      }
      forces.wait(std::chrono::milliseconds(2));
      states.take([&](const HapticState& s) {
        if (s.device() == "omni") sent[s.seq()] = s.stamp().wall_time_ns();
      });
      const std::int64_t now = runtime::wall_ns();
      forces.take([&](const ForceFeedback& f) {
        auto it = sent.find(f.answers_seq());
        if (f.device() == "omni" && it != sent.end()) rtt_us.add((now - it->second) * 1e-3);
      });
      status.take([&](const ServiceStatus& s) { overruns[s.service().to_string()] = s.overruns(); });
      meshes.take([](const DeformedMesh&) {});
      bodies.take([](const RigidBodyState&) {});
      poses.take([](const MarkerPose&) {});
      // Seqs older than a second are answered or never will be.
      if (sent.size() > 4000)
        for (auto it = sent.begin(); it != sent.end();) it = now - it->second > 1'000'000'000 ? sent.erase(it) : ++it;
    }
    if (waitpid(up, nullptr, WNOHANG) == up)
      throw std::runtime_error("soak: the deployment ended early:\n" + tail(log));
    double rss = 0;
    for (const auto& [name, pid] : pids) rss += rss_kb(pid);
    double over = 0, haptic_over = 0;
    for (const auto& [name, n] : overruns) over += double(n), haptic_over += haptic.count(name) ? double(n) : 0;
    const double l = lost();
    rows.push_back({"window",
                    {{"t_s", w * window}},
                    {{"rss_mb", rss / 1024},
                     {"overruns", over - overruns_before},
                     {"haptic_overruns", haptic_over - haptic_before},
                     {"reliable_lost", l - lost_before},
                     {"haptic_rtt_p50_us", rtt_us.percentile(0.5)},
                     {"haptic_rtt_p99_us", rtt_us.percentile(0.99)},
                     {"answers", double(rtt_us.size())}}});
    progress("soak: " + text(w * window) + " s: rss " + text(rss / 1024) + " MB, haptic round trip p99 " +
             text(rtt_us.percentile(0.99)) + " us, " + text(l - lost_before) + " lost, " +
             text(over - overruns_before) + " overruns");
    lost_before = l, overruns_before = over, haptic_before = haptic_over;
    rtt_us.clear();
  }
  stop();

  auto metric = [](const Row& r, const std::string& k) -> double {
    for (const auto& [name, v] : r.metrics)
      if (name == k) return v;
    return NAN;
  };
  const Row& first = rows.front();
  const Row& last = rows.back();
  double lost_all = 0, over_all = 0, haptic_all = 0;
  for (const Row& r : rows)
    lost_all += metric(r, "reliable_lost"), over_all += metric(r, "overruns"),
        haptic_all += metric(r, "haptic_overruns");
  const double p99_0 = metric(first, "haptic_rtt_p99_us");
  rows.push_back({"summary",
                  {{"seconds", total}},
                  {{"rss_growth_pct", 100 * (metric(last, "rss_mb") / metric(first, "rss_mb") - 1)},
                   {"reliable_lost", lost_all},
                   {"p99_drift_pct", 100 * std::abs(metric(last, "haptic_rtt_p99_us") - p99_0) / p99_0},
                   {"overruns", over_all},
                   {"haptic_overruns", haptic_all},
                   {"windows", double(rows.size())}}});
  return rows;
}

}  // namespace

Suite soak_suite() {
  Suite s{"soak",
          "the default deployment in real time for 30 min (30 s with --quick): memory, loss, overruns, haptic "
          "round trip over time",
          soak_rows};
  s.tables = {
      {"window",
       "deploy/default.yaml's scene and services in real time, the tour played again and again, one row per "
       "window: the services' resident memory at its end (sum of VmRSS), their overruns in it (ServiceStatus), "
       "samples Fast DDS reports lost to the bench's readers of DeformedMesh, RigidBodyState, MarkerPose and "
       "ServiceStatus (reliable), haptic_overruns those of the haptic-rate services (haptic, rigid, deformable: "
       "the ones whose haptic threads run first), and the haptic round trip the bench sees (HapticState sent, by its "
       "stamp, "
       "to each ForceFeedback answering it received), p50 and p99 over the window."},
      {"summary",
       "The whole run: rss_growth_pct is the last window's memory against the first's, p99_drift_pct the "
       "last window's round-trip p99 against the first's (absolute), reliable_lost and overruns summed."}};
  s.plots = {{"window", "t_s", "haptic_rtt_p99_us", "time (s)", "haptic round trip p99 (us)", {}, {}, {}, false, false},
             {"window", "t_s", "rss_mb", "time (s)", "services' resident memory (MB)", {}, {}, {}, false, false}};
  s.goals = {{"memory grows under 1% from the first window to the last", "summary", "rss_growth_pct", 1},
             {"no sample lost on reliable topics", "summary", "reliable_lost", 0},
             {"haptic round-trip p99 within 20% from the first window to the last", "summary", "p99_drift_pct", 20},
             {"no overrun on the haptic-rate services (haptic, rigid, deformable) in any window", "summary",
              "haptic_overruns", 0}};
  return s;
}

}  // namespace hcosim::services::bench
