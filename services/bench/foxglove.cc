// bench foxglove: the live Foxglove bridge's cost at the default scene.
//
// run: deploy/default.yaml's scene and services in real time through
//   hcosim up, in turn without the bridge and with it (a foxglove service
//   and a client, services/foxglove/client.h, subscribed to every channel
//   it advertises, in the bench's process): the device's round trip and
//   in-tick share from its closing report, and with the bridge its
//   process's CPU time (/proc) over a window before the client connects
//   (what receiving every topic costs) and over the measured window after,
//   and what the client received. Runs alternate, so that a drift of the
//   machine's load falls on both.
// bridge: over the pairs, the bridge's median CPU shares of one core and
//   the median round-trip p99 with the bridge against without it.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "adapters/json.h"
#include "services/bench/bench.h"
#include "services/bench/harness.h"
#include "services/foxglove/client.h"
#include "services/runtime/service.h"

namespace hcosim::services::bench {
namespace {

namespace fs = std::filesystem;

// A process's CPU time so far (user and system), s.
double cpu_s(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // After the command's closing parenthesis: fields 3.. ; utime and stime are 14 and 15.
  std::istringstream rest(stat.substr(stat.rfind(')') + 2));
  std::string field;
  double ticks = 0;
  for (int i = 3; i <= 15 && rest >> field; ++i)
    if (i >= 14) ticks += std::stod(field);
  return ticks / double(sysconf(_SC_CLK_TCK));
}

// What `text` says after `pattern`'s one group, or throws naming `what`.
std::string find(const std::string& text, const std::string& pattern, const std::string& what) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) throw std::runtime_error("bench foxglove: no " + what);
  return m[1];
}

// The port the bridge says it serves at in its log `fox_log`, read until
// it says so (within 60 s, while `up` runs): on this loaded machine the
// bridge's start took 2 to 4 s, and one read a second after "every
// service running" found no port in three runs of six.
std::string serving(pid_t up, const fs::path& fox_log) {
  const std::int64_t deadline = runtime::mono_ns() + std::int64_t(60e9);
  const std::regex line(R"(serving ws://127\.0\.0\.1:(\d+))");
  for (;;) {
    std::smatch m;
    const std::string text = read_all(fox_log);
    if (std::regex_search(text, m, line)) return m[1];
    if (runtime::mono_ns() > deadline || waitpid(up, nullptr, WNOHANG) == up)
      throw std::runtime_error("bench foxglove: the bridge never said where it serves, see " + fox_log.string());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

struct Run {
  double rtt_p50_us = NAN, rtt_p99_us = NAN, in_tick = NAN, cpu_share = NAN, cpu_share_no_client = NAN, seconds = 0;
  foxglove::ClientCounts client;
};

// The bridge's CPU share of one core over `seconds` from now.
double cpu_share_over(pid_t pid, double seconds) {
  const double cpu0 = cpu_s(pid);
  const std::int64_t t0 = runtime::mono_ns();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  return (cpu_s(pid) - cpu0) / ((runtime::mono_ns() - t0) * 1e-9);
}

// `idle` s before the client connects (both runs wait as long, so that
// their round trips cover the same stretch of the tour), then `seconds`
// measured with it.
Run run(const Context& c, const fs::path& dir, bool bridge, double idle, double seconds) {
  fs::create_directories(dir);
  const fs::path report = dir / "omni.json", log = dir / "up.log";
  fs::remove(report);
  const fs::path file = default_deployment(dir, c.domain, idle + seconds + 10, idle + seconds + 5, report);
  if (bridge) {
    YAML::Node d = YAML::LoadFile(file.string());
    YAML::Node fox;
    fox["name"] = "fox", fox["kind"] = "foxglove", fox["rate"] = 20, fox["params"]["port"] = 0;
    d["services"].push_back(fox);
    std::ofstream(file) << YAML::Dump(d) << "\n";
  }
  const pid_t up = start_up(file, dir / "out", log);
  wait_running(up, log, "bench foxglove");
  Run r;
  try {
    std::unique_ptr<foxglove::Client> client;
    pid_t fox = 0;
    std::this_thread::sleep_for(std::chrono::seconds(1));  // every reader matched
    if (bridge) {
      const int port = std::stoi(serving(up, dir / "out" / "logs" / "fox.log"));
      fox = pid_t(std::stoi(find(read_all(log), R"(started fox +pid (\d+))", "bridge pid in " + log.string())));
      r.cpu_share_no_client = cpu_share_over(fox, idle);
      client = std::make_unique<foxglove::Client>("127.0.0.1", port);
    } else {
      std::this_thread::sleep_for(std::chrono::duration<double>(idle));
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));  // connected and subscribed
    const std::int64_t t0 = runtime::mono_ns();
    if (fox)
      r.cpu_share = cpu_share_over(fox, seconds);
    else
      std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    r.seconds = (runtime::mono_ns() - t0) * 1e-9;
    if (client) {
      r.client = client->counts();
      client.reset();
    }
  } catch (...) {
    // Nothing left behind: the deployment stops with the bench.
    kill(up, SIGINT);
    waitpid(up, nullptr, 0);
    throw;
  }
  int status = 0;
  waitpid(up, &status, 0);
  const std::string json = read_all(report);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || json.empty())
    throw std::runtime_error("bench foxglove: the default deployment failed (status " + std::to_string(status) +
                             "), see " + log.string());
  const adapters::Json j = adapters::parse_json(json, "bench foxglove: the device's report");
  r.rtt_p50_us = j["p50_us"].get<double>(), r.rtt_p99_us = j["p99_us"].get<double>();
  r.in_tick = j["on_time_ratio"].get<double>();
  return r;
}

std::vector<Row> foxglove_rows(const Context& c) {
  const int pairs = c.quick ? 1 : 3;
  const double idle = c.quick ? 5 : 10, seconds = c.quick ? 20 : 30;
  std::vector<Row> rows;
  std::vector<double> cpu, cpu_idle, p99_on, p99_off, tick_on, tick_off, mb;
  for (int k = 0; k < pairs; ++k) {
    for (const bool bridge : {false, true}) {
      progress(
          "foxglove pair " + std::to_string(k + 1) + " of " + std::to_string(pairs) + ": the default scene " +
          (bridge ? "with the bridge, " + std::to_string(int(idle)) + " s alone, then " + std::to_string(int(seconds)) +
                        " s with a client subscribed to everything"
                  : "without the bridge, " + std::to_string(int(idle)) + " + " + std::to_string(int(seconds)) + " s"));
      const Run r =
          run(c, c.work / ("foxglove_" + std::to_string(k) + (bridge ? "_on" : "_off")), bridge, idle, seconds);
      const auto rate = [&](const std::string& topic) {
        const auto it = r.client.per_topic.find(topic);
        return it == r.client.per_topic.end() ? 0.0 : double(it->second) / r.seconds;
      };
      Row row{"run",
              {{"pair", double(k + 1)}, {"bridge", std::string(bridge ? "on" : "off")}, {"seconds", seconds}},
              {{"rtt_p50_us", r.rtt_p50_us}, {"rtt_p99_us", r.rtt_p99_us}, {"in_tick_ratio", r.in_tick}}};
      if (bridge) {
        const double mb_s = double(r.client.bytes) / 1e6 / r.seconds;
        row.metrics.insert(row.metrics.end(), {{"cpu_share", r.cpu_share},
                                               {"cpu_share_no_client", r.cpu_share_no_client},
                                               {"channels", double(r.client.channels)},
                                               {"client_mb_per_s", mb_s},
                                               {"client_messages_per_s", double(r.client.messages) / r.seconds},
                                               {"cube_scene_per_s", rate("scene/cube")},
                                               {"organ_scene_per_s", rate("scene/organ")},
                                               {"images_per_s", rate("image/cam")},
                                               {"statuses", double(r.client.statuses)}});
        cpu.push_back(r.cpu_share), cpu_idle.push_back(r.cpu_share_no_client);
        p99_on.push_back(r.rtt_p99_us), tick_on.push_back(r.in_tick), mb.push_back(mb_s);
      } else {
        p99_off.push_back(r.rtt_p99_us), tick_off.push_back(r.in_tick);
      }
      rows.push_back(row);
    }
  }
  rows.push_back({"bridge",
                  {{"pairs", double(pairs)}, {"seconds", seconds}},
                  {{"cpu_share", median(cpu)},
                   {"cpu_share_no_client", median(cpu_idle)},
                   {"client_mb_per_s", median(mb)},
                   {"rtt_p99_us", median(p99_on)},
                   {"rtt_p99_us_without", median(p99_off)},
                   {"p99_change", median(p99_on) / median(p99_off) - 1},
                   {"in_tick_ratio", median(tick_on)},
                   {"in_tick_ratio_without", median(tick_off)}}});
  return rows;
}

}  // namespace

Suite foxglove_suite() {
  Suite s{"foxglove",
          "the live Foxglove bridge at the default scene: its CPU share and the haptic round trip with a client "
          "subscribed to everything, against the same scene without it, in turn",
          foxglove_rows};
  s.tables = {
      {"run",
       "deploy/default.yaml's scene and services in real time through hcosim up, without and with the bridge (a "
       "foxglove service, and a client in the bench's process subscribed to every channel it advertises), in turn: "
       "the device's round trip and in-tick share over the run; with the bridge, its process's CPU time (/proc, a "
       "share of one core) over the measured window with the client (cpu_share) and over a window before the "
       "client connects (cpu_share_no_client: receiving and checking every topic, serving no one), and what the "
       "client received a second."},
      {"bridge",
       "Over the pairs: the bridge's median CPU shares with and without the client and the client's MB/s, the "
       "median round-trip p99 with the bridge against without it (p99_change = with / without - 1), and the median "
       "in-tick shares."}};
  s.goals = {
      {"the bridge at most 10% of one core at the default scene, a client subscribed to everything", "bridge",
       "cpu_share", 0.10},
      {"the haptic round-trip p99 changed by under 10% by the bridge and its client", "bridge", "p99_change", 0.10}};
  return s;
}

}  // namespace hcosim::services::bench
