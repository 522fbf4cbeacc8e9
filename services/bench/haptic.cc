// bench haptic: the haptic device's closed loop and its force rendering.
//
// closed_loop_rtt: hcosim_haptic at 1 kHz, waiting up to 0.8 ms each tick
//   for the force answering that tick's HapticState, from a force-producing
//   peer in another process (the hcosim runtime's pong, a wall at z = 0).
//   The round trip is measured by the device service itself.
// bare_fastdds_rtt: the same payloads and QoS kinds between two processes
//   using Fast DDS alone, measured in the same run; within_0_8ms_ratio is
//   the closed loop's on-time test applied to it.
// deployment: the default scene (deploy/default.yaml's objects, camera and
//   view) in real time through hcosim up, the device's closing report
//   (jitter, the share of ticks every source answered within, round trip,
//   rendered-force error against the run's peak force), and a bare Fast DDS
//   ping-pong pair at 1 kHz beside it on the next domain, both ends (and
//   their Fast DDS threads) at the haptic threads' priority, whose pinging
//   loop's wake-up lateness is the bare timer's jitter under the same load.
// wall: the stiff-wall rig (adapters/device/wall_rig.h) per delay and
//   stiffness: the largest force output, the device's net work on the tip,
//   whether the contact settled, the settled depth's error from where the
//   hand's pull balances the wall, and the largest force over that
//   balance's force, less 1 (overshoot).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "adapters/deployment.h"
#include "adapters/device/wall_rig.h"
#include "adapters/json.h"
#include "services/bench/bench.h"
#include "services/bench/harness.h"
#include "services/bench/peer.h"
#include "services/runtime/service.h"

namespace hcosim::services::bench {
namespace {

namespace fs = std::filesystem;

// The figure `key` of the device's JSON report; null (a figure of no
// sample, such as the error of no late answer) is NaN.
double field(const std::string& json, const std::string& key) {
  const adapters::Json j = adapters::parse_json(json, "bench haptic: the device's report");
  if (!j.contains(key)) throw std::runtime_error("bench haptic: no '" + key + "' in the device's report: " + json);
  return j[key].is_number() ? j[key].get<double>() : NAN;
}

Row closed_loop(const Context& c, double seconds) {
  const fs::path dir = c.work / "haptic_run";
  fs::create_directories(dir);
  std::ofstream(dir / "hold.yaml") << "start: [0, 0, 0.001]\nactions:\n  - press: {depth: 0.003, speed: 0.01}\n"
                                      "  - hold: {duration: 1000}\n";
  std::ofstream(dir / "deploy.yaml") << "domain: " << c.domain << "\nmode: realtime\nservices:\n"
                                     << "  - name: omni\n    kind: haptic\n    rate: 1000\n"
                                     << "    params: {script: hold.yaml, answer_wait: 0.0008, report: omni.json}\n";
  fs::remove(dir / "omni.json");
  const pid_t peer = start_peer("hcosim", c.domain, seconds + 5);
  const std::string haptic = (fs::read_symlink("/proc/self/exe").parent_path() / "hcosim_haptic").string();
  const std::string log = (dir / "omni.log").string();
  const pid_t dev = fork();
  if (dev == 0) {
    freopen(log.c_str(), "w", stdout);
    freopen(log.c_str(), "a", stderr);
    execl(haptic.c_str(), haptic.c_str(), "--name", "omni", "--rate", "1000", "--domain",
          std::to_string(c.domain).c_str(), "--duration", std::to_string(seconds).c_str(), "--deployment",
          (dir / "deploy.yaml").c_str(), nullptr);
    _exit(127);
  }
  int status = 0;
  waitpid(dev, &status, 0);
  stop(peer);
  std::ifstream in(dir / "omni.json");
  std::stringstream json;
  json << in.rdbuf();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || json.str().empty())
    throw std::runtime_error("bench haptic: hcosim_haptic failed (status " + std::to_string(status) + "), see " + log);
  return {"closed_loop_rtt",
          {{"rate_hz", 1000.0}, {"seconds", seconds}, {"answer_wait_ms", 0.8}},
          {{"p50_us", field(json.str(), "p50_us")},
           {"p99_us", field(json.str(), "p99_us")},
           {"on_time_ratio", field(json.str(), "on_time_ratio")},
           {"ticks", field(json.str(), "ticks")}}};
}

Row deployment(const Context& c, double seconds) {
  const fs::path dir = fs::absolute(c.work / "haptic_deployment");
  fs::create_directories(dir);
  const fs::path report = dir / "omni.json", log = dir / "up.log";
  fs::remove(report);
  const fs::path file = default_deployment(dir, c.domain, seconds + 10, seconds, report);
  const pid_t up = start_up(file, dir / "out", log);
  // The bare pair runs once every service does (the run's duration counts
  // from then), and ends before it.
  wait_running(up, log, "bench haptic");
  const Rtt bare = bare_rtt(c.domain + 1, std::max(1.0, seconds - 4), adapters::kHapticPriority);
  int status = 0;
  waitpid(up, &status, 0);
  const std::string json = read_all(report);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || json.empty())
    throw std::runtime_error("bench haptic: the default deployment failed (status " + std::to_string(status) +
                             "), see " + log.string());
  const double p99 = field(json, "p99_us"), bare_p99 = bare.us.percentile(0.99), peak = field(json, "peak_force_n");
  return {"deployment",
          {{"seconds", seconds}},
          {{"jitter_p50_us", field(json, "jitter_p50_us")},
           {"jitter_p99_us", field(json, "jitter_p99_us")},
           {"bare_jitter_p50_us", bare.late_us.percentile(0.5)},
           {"bare_jitter_p99_us", bare.late_us.percentile(0.99)},
           {"in_tick_ratio", field(json, "on_time_ratio")},
           {"rtt_p50_us", field(json, "p50_us")},
           {"rtt_p99_us", p99},
           {"bare_p50_us", bare.us.percentile(0.5)},
           {"bare_p99_us", bare_p99},
           // The in-tick test applied to the bare pair beside the scene.
           {"bare_within_0_8ms_ratio", bare.sent ? double(bare.us.count_at_most(800)) / double(bare.sent) : 0},
           {"p99_ratio_to_bare", p99 / bare_p99},
           {"force_error_p99_n", field(json, "force_error_p99_n")},
           {"peak_force_n", peak},
           {"force_error_share", peak > 0 ? field(json, "force_error_p99_n") / peak : NAN},
           {"covered_source_ticks", field(json, "covered")},
           {"ticks", field(json, "ticks")}}};
}

std::vector<Row> haptic_rows(const Context& c) {
  const double seconds = c.quick ? 10 : 60;
  std::vector<Row> rows;
  progress("haptic closed loop: hcosim_haptic and a force peer, " + std::to_string(int(seconds)) + " s at 1 kHz");
  rows.push_back(closed_loop(c, seconds));
  progress("haptic bare Fast DDS round trip, " + std::to_string(int(seconds)) + " s at 1 kHz");
  const Rtt bare = bare_rtt(c.domain, seconds);
  rows.push_back({"bare_fastdds_rtt",
                  {{"rate_hz", 1000.0}, {"seconds", seconds}},
                  {{"p50_us", bare.us.percentile(0.5)},
                   {"p99_us", bare.us.percentile(0.99)},
                   {"loss_ratio", bare.sent ? double(bare.lost) / double(bare.sent) : 1.0},
                   // The closed loop's on-time test applied to bare Fast DDS:
                   // answered within 0.8 ms of sending.
                   {"within_0_8ms_ratio", bare.sent ? double(bare.us.count_at_most(800)) / double(bare.sent) : 0}}});
  rows[0].metrics.push_back({"p99_ratio_to_bare", rows[0].metrics[1].second / rows[1].metrics[1].second});
  const double scene_s = c.quick ? 20 : 60;
  progress("haptic default deployment in real time, " + std::to_string(int(scene_s)) +
           " s, a bare Fast DDS pair beside it at the haptic priority");
  rows.push_back(deployment(c, scene_s));
  progress("haptic wall rig: stiffness 250 to 1000 N/m, delay 0 to 5 ms");
  for (const double k : {250.0, 500.0, 1000.0})
    for (const double delay_ms : {0.0, 1.0, 2.0, 3.0, 5.0}) {
      adapters::device::WallRig rig;
      rig.wall.stiffness = k;
      rig.delay_s = delay_ms * 1e-3;
      const adapters::device::WallRun run = adapters::device::run_wall(rig);
      rows.push_back({"wall",
                      {{"delay_ms", delay_ms}, {"stiffness_n_per_m", k}},
                      {{"max_force_n", run.max_force_n},
                       {"energy_out_j", run.max_energy_out_j},
                       {"stable", run.stable ? 1.0 : 0.0},
                       {"depth_error", run.depth_m / adapters::device::balance_depth(rig) - 1},
                       {"overshoot", run.max_force_n / (k * adapters::device::balance_depth(rig)) - 1}}});
    }
  return rows;
}

}  // namespace

Suite haptic_suite() {
  Suite s{"haptic",
          "haptic device: closed-loop round trip through hcosim_haptic against bare Fast DDS, the default scene's "
          "haptic loop in real time, and the stiff wall with 0 to 5 ms of force delay",
          haptic_rows};
  s.tables = {
      {"closed_loop_rtt",
       "hcosim_haptic at 1 kHz waiting up to 0.8 ms each tick for the force answering that tick's state, from a "
       "force peer in another process; round trips measured by the device service over every tick; on_time_ratio: "
       "ticks whose answer came in time; the ratio is to bare_fastdds_rtt below, same run."},
      {"bare_fastdds_rtt",
       "The same payloads and QoS kinds between two processes with Fast DDS alone, measured in the same run: the "
       "baseline; within_0_8ms_ratio applies the closed loop's on-time test to it."},
      {"deployment",
       "deploy/default.yaml's scene and services in real time through hcosim up (its tour repeated): the device's "
       "wake-up jitter, in_tick_ratio (ticks whose every source answered within the tick), its round trip, and "
       "the rendered-force error p99 (a late answer against what the device rendered from the local model) as a "
       "share of the run's peak force; bare_* is a Fast DDS ping-pong pair at 1 kHz run beside it on the next "
       "domain, both ends at the haptic threads' SCHED_FIFO priority (bare_within_0_8ms_ratio: its round trips "
       "within the device's 0.8 ms wait); bare_jitter_* is its pinging loop's wake-up "
       "lateness (clock_nanosleep to an absolute time, as the device's loop), what the timer itself gives there; "
       "covered_source_ticks: sources rendered from a free-space answer, not waited for."},
      {"wall",
       "The stiff-wall rig (adapters/device/wall_rig.h, passivity controller on) pressed 1 cm behind a wall of each "
       "stiffness with 0 to 5 ms of force delay: the largest force, the device's net work on the tip (energy_out_j, "
       "positive is energy the device created), whether it settled, the settled depth's error and the force "
       "overshoot over the balance force."}};
  s.plots = {{"wall",
              "delay_ms",
              "overshoot",
              "force delay (ms)",
              "force overshoot (fraction of the balance force)",
              {"stiffness_n_per_m"},
              {},
              {},
              false,
              false}};
  s.goals = {
      {"the closed loop's p99 within 1.25 times bare Fast DDS's", "closed_loop_rtt", "p99_ratio_to_bare", 1.25},
      {"at least 99.9% of ticks answered in time", "closed_loop_rtt", "on_time_ratio", 0.999, "", "", true},
      {"at least 99.9% of the default scene's ticks answered by every source within the tick", "deployment",
       "in_tick_ratio", 0.999, "", "", true},
      {"the default scene's round-trip p99 within 1.5 times bare Fast DDS's beside it", "deployment",
       "p99_ratio_to_bare", 1.5},
      {"the device loop's wake-up jitter p99 at most 100 us in the default scene", "deployment", "jitter_p99_us", 100},
      {"the rendered-force error p99 at most 5% of the peak force", "deployment", "force_error_share", 0.05},
      {"every wall contact settles", "wall", "stable", 1, "", "", true},
      {"no energy created by the wall (energy_out_j at most 1 mJ)", "wall", "energy_out_j", 1e-3}};
  return s;
}

}  // namespace hcosim::services::bench
