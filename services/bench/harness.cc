#include "services/bench/harness.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <yaml-cpp/yaml.h>

#include "services/runtime/participant.h"
#include "services/runtime/realtime.h"

namespace fs = std::filesystem;

namespace hcosim::services::bench {

pid_t start_self(const std::vector<std::string>& on, const std::vector<std::string>& args) {
  std::vector<std::string> all = on;
  all.push_back(fs::read_symlink("/proc/self/exe").string());
  all.insert(all.end(), args.begin(), args.end());
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

pid_t start_up(const fs::path& deployment, const fs::path& out, const fs::path& log, const fs::path& record) {
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const pid_t pid = fork();
  if (pid == 0) {
    freopen(log.c_str(), "w", stdout);
    freopen(log.c_str(), "a", stderr);
    if (record.empty())
      execl(self.c_str(), self.c_str(), "up", deployment.c_str(), "--out", out.c_str(), nullptr);
    else
      execl(self.c_str(), self.c_str(), "up", deployment.c_str(), "--out", out.c_str(), "--record", record.c_str(),
            nullptr);
    _exit(127);
  }
  return pid;
}

std::string read_all(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void wait_running(pid_t up, const fs::path& log, const std::string& what) {
  const std::int64_t deadline = runtime::mono_ns() + std::int64_t(120e9);
  while (read_all(log).find("every service running") == std::string::npos) {
    if (runtime::mono_ns() > deadline || waitpid(up, nullptr, WNOHANG) == up) {
      kill(up, SIGINT);
      waitpid(up, nullptr, 0);
      throw std::runtime_error(what + ": the default deployment did not start, see " + log.string());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

fs::path default_deployment(const fs::path& folder, int domain, double seconds, double duration,
                            const fs::path& device_report) {
  // The file names its script by an absolute path: a relative one would be
  // taken from the file's folder.
  const fs::path dir = fs::absolute(folder);
  const fs::path deploy = fs::path(runtime::default_qos_file()).parent_path();
  YAML::Node tour = YAML::LoadFile((deploy / "scripts" / "tour.yaml").string());
  YAML::Node actions(YAML::NodeType::Sequence);
  // One tour takes about 20 s: enough of them for the run, and one more.
  for (int k = 0; k < int(seconds / 20) + 2; ++k)
    for (const auto& a : tour["actions"]) actions.push_back(YAML::Clone(a));
  tour["actions"] = actions;
  std::ofstream(dir / "tour_loop.yaml") << YAML::Dump(tour) << "\n";

  YAML::Node d = YAML::LoadFile((deploy / "default.yaml").string());
  d["domain"] = domain;
  // The scene's files (the organ's mesh) are the deploy folder's.
  for (auto o : d["scene"]["objects"])
    if (o["mesh"] && fs::path(o["mesh"].as<std::string>()).is_relative())
      o["mesh"] = (deploy / o["mesh"].as<std::string>()).string();
  d["mode"] = "realtime";
  d["duration"] = duration;
  for (auto s : d["services"]) {
    if (s["kind"].as<std::string>() == "haptic") {
      s["params"]["script"] = (dir / "tour_loop.yaml").string();
      if (!device_report.empty()) s["params"]["report"] = device_report.string();
    }
    if (s["kind"].as<std::string>() == "ar_view") s["params"].remove("snapshots");
  }
  const fs::path file = dir / "deploy.yaml";
  std::ofstream(file) << YAML::Dump(d) << "\n";
  return file;
}

bool reap(pid_t pid, double seconds) {
  int status = 0;
  const std::int64_t deadline = runtime::mono_ns() + std::int64_t(seconds * 1e9);
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (runtime::mono_ns() > deadline) {
      kill(pid, SIGTERM);
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void stop(pid_t pid) {
  kill(pid, SIGTERM);
  int status;
  waitpid(pid, &status, 0);
}

}  // namespace hcosim::services::bench
