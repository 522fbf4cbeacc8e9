#include "services/bench/hosts.h"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace hcosim::services::bench {

namespace fs = std::filesystem;

namespace {

// Runs a shell command, its output into `log`; true on exit status 0.
bool sh(const std::string& command, const fs::path& log) {
  return std::system((command + " >>'" + log.string() + "' 2>&1").c_str()) == 0;
}

// The last non-empty line of `file`: what a failed command said.
std::string last_line(const fs::path& file) {
  std::ifstream in(file);
  std::string last;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) last = line;
  return last;
}

}  // namespace

std::unique_ptr<Hosts> Hosts::make(int domain, int n, const fs::path& work, std::string& why) {
  if (geteuid() != 0) {
    why = "making network namespaces needs root";
    return nullptr;
  }
  if (std::system("command -v ip >/dev/null 2>&1") != 0) {
    why = "no ip (iproute2)";
    return nullptr;
  }
  std::unique_ptr<Hosts> h(new Hosts);
  const std::string tag = std::to_string(domain % 1000);
  h->bridge_ = "hcbd" + tag;
  h->net_ = "10." + std::to_string(150 + domain % 100) + ".0";
  fs::create_directories(work);
  const fs::path log = work / "hosts.log";
  for (int i = 0; i < n; ++i) {
    h->names_.push_back("hcbd" + tag + "h" + std::to_string(i + 1));
    h->shm_.push_back(work / ("shm_" + std::to_string(i + 1)));
  }
  h->remove();  // a killed run's left-overs
  bool ok = sh("ip link add " + h->bridge_ + " type bridge && ip link set " + h->bridge_ + " up", log);
  for (int i = 0; ok && i < n; ++i) {
    const std::string& ns = h->names_[std::size_t(i)];
    fs::create_directories(h->shm_[std::size_t(i)]);
    ok = sh("ip netns add " + ns + " && ip link add " + ns + " type veth peer name eth0 netns " + ns +
                " && ip link set " + ns + " master " + h->bridge_ + " up && ip netns exec " + ns + " ip addr add " +
                h->address(i) + "/24 dev eth0 && ip netns exec " + ns + " ip link set eth0 up && ip netns exec " + ns +
                " ip link set lo up",
            log);
  }
  if (!ok) {
    why = "cannot make the hosts: " + last_line(log);
    return nullptr;  // the destructor removes what was made
  }
  h->rig_ = work / "rig.yaml";
  std::ofstream rig(h->rig_);
  rig << "domain: " << domain << "\nnetwork: {}\nhosts:\n";
  for (int i = 0; i < n; ++i) rig << "  - {name: " << h->name(i) << ", address: " << h->address(i) << "}\n";
  // The round trips' peer runs the service runtime, which finds its name in the file.
  rig << "services:\n  - {name: bench_peer, kind: haptic, rate: 1000, host: " << h->name(1) << "}\n";
  if (!rig.flush()) {
    why = "cannot write " + h->rig_.string();
    return nullptr;
  }
  return h;
}

Hosts::~Hosts() { remove(); }

void Hosts::remove() const {
  for (const std::string& ns : names_)
    std::system(("for p in $(ip netns pids " + ns + " 2>/dev/null); do kill -KILL $p; done; ip netns del " + ns +
                 " 2>/dev/null")
                    .c_str());
  if (!bridge_.empty()) std::system(("ip link del " + bridge_ + " 2>/dev/null").c_str());
  for (const fs::path& p : shm_) {
    std::error_code ec;
    fs::remove_all(p, ec);
  }
}

std::vector<std::string> Hosts::exec(int host) const {
  return {"ip",
          "netns",
          "exec",
          names_.at(std::size_t(host)),
          "sh",
          "-c",
          "mount --bind \"$0\" /dev/shm && exec \"$@\"",
          shm_.at(std::size_t(host)).string()};
}

void Hosts::enter(int host) const {
  const std::string path = "/run/netns/" + names_.at(std::size_t(host));
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0 || setns(fd, CLONE_NEWNET) != 0) {
    if (fd >= 0) close(fd);
    throw std::runtime_error("bench: cannot enter the network namespace " + path);
  }
  close(fd);
}

std::string Hosts::address(int host) const { return net_ + "." + std::to_string(host + 1); }

}  // namespace hcosim::services::bench
