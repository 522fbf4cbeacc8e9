// bench haptic: the haptic device's closed loop and its force rendering.
//
// closed_loop_rtt: hcosim_haptic at 1 kHz, waiting up to 0.8 ms each tick
//   for the force answering that tick's HapticState, from a force-producing
//   peer in another process (the hcosim runtime's pong, a wall at z = 0).
//   The round trip is measured by the device service itself.
// bare_fastdds_rtt: the same payloads and QoS kinds between two processes
//   using Fast DDS alone, measured in the same run; within_0_8ms_ratio is
//   the closed loop's on-time test applied to it.
// wall: the stiff-wall rig (adapters/device/wall_rig.h) per delay and
//   stiffness: the largest force output, the device's net work on the tip,
//   whether the contact settled, the settled depth's error from where the
//   hand's pull balances the wall, and the largest force over that
//   balance's force, less 1 (overshoot).
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "bench.h"
#include "device/wall_rig.h"

namespace hcosim::cli {
namespace {

namespace fs = std::filesystem;

// The number after "key": in a one-line JSON report.
double field(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\":([-0-9.eE+]+|nan|inf)")))
    throw std::runtime_error("bench haptic: no '" + key + "' in the device's report: " + json);
  return std::stod(m[1]);
}

Row closed_loop(const Context& c, double seconds) {
  const fs::path dir = c.out / "haptic_run";
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
  stop_peer(peer);
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
  progress("haptic wall rig: stiffness 250 to 1000 N/m, delay 0 to 5 ms");
  for (const double k : {250.0, 500.0, 1000.0})
    for (const double delay_ms : {0.0, 1.0, 2.0, 3.0, 5.0}) {
      device::WallRig rig;
      rig.wall.stiffness = k;
      rig.delay_s = delay_ms * 1e-3;
      const device::WallRun run = device::run_wall(rig);
      rows.push_back({"wall",
                      {{"delay_ms", delay_ms}, {"stiffness_n_per_m", k}},
                      {{"max_force_n", run.max_force_n},
                       {"energy_out_j", run.max_energy_out_j},
                       {"stable", run.stable ? 1.0 : 0.0},
                       {"depth_error", run.depth_m / device::balance_depth(rig) - 1},
                       {"overshoot", run.max_force_n / (k * device::balance_depth(rig)) - 1}}});
    }
  return rows;
}

}  // namespace

Suite haptic_suite() {
  Suite s{"haptic",
          "haptic device: closed-loop round trip through hcosim_haptic against bare Fast DDS, and the stiff wall "
          "with 0 to 5 ms of force delay",
          haptic_rows};
  s.tables = {
      {"closed_loop_rtt",
       "hcosim_haptic at 1 kHz waiting up to 0.8 ms each tick for the force answering that tick's state, from a "
       "force peer in another process; round trips measured by the device service over every tick; on_time_ratio: "
       "ticks whose answer came in time; the ratio is to bare_fastdds_rtt below, same run."},
      {"bare_fastdds_rtt",
       "The same payloads and QoS kinds between two processes with Fast DDS alone, measured in the same run: the "
       "baseline; within_0_8ms_ratio applies the closed loop's on-time test to it."},
      {"wall",
       "The stiff-wall rig (adapters/device/wall_rig.h, passivity controller on) pressed 1 cm behind a wall of each "
       "stiffness with 0 to 5 ms of force delay: the largest force, the device's net work on the tip (energy_out_j, "
       "positive is energy the device created), whether it settled, the settled depth's error and the force "
       "overshoot over the balance force."}};
  s.plots = {{"wall", "delay_ms", "overshoot", "force delay (ms)", "force overshoot (fraction of the balance force)",
              {"stiffness_n_per_m"}, {}, {}, false, false}};
  s.goals = {{"the closed loop's p99 within 1.25 times bare Fast DDS's", "closed_loop_rtt", "p99_ratio_to_bare", 1.25},
             {"at least 99.9% of ticks answered in time", "closed_loop_rtt", "on_time_ratio", 0.999, "", "", true},
             {"every wall contact settles", "wall", "stable", 1, "", "", true},
             {"no energy created by the wall (energy_out_j at most 1 mJ)", "wall", "energy_out_j", 1e-3}};
  return s;
}

}  // namespace hcosim::cli
