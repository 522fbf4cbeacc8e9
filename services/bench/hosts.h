// Hosts made of Linux network namespaces, for the rows measured over UDP
// between hosts (bench dds): each host a namespace with its own address on
// one bridge and its own /dev/shm, so that nothing but UDP on the bridge
// joins them, and every address used lives only inside them.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace hcosim::services::bench {

class Hosts {
 public:
  // `n` hosts, named and addressed from `domain` (10.(150 + domain % 100).0.1
  // and up), their /dev/shm folders under `work`; nullptr, with `why`,
  // where this machine cannot make them (not root, no iproute2, no veth,
  // bridge or namespaces).
  static std::unique_ptr<Hosts> make(int domain, int n, const std::filesystem::path& work, std::string& why);
  // Kills what still runs in them, then removes them, the bridge and the folders.
  ~Hosts();
  Hosts(const Hosts&) = delete;
  Hosts& operator=(const Hosts&) = delete;

  // The command that runs a program (appended) on `host`, 0-based: in its
  // namespace, with its /dev/shm.
  std::vector<std::string> exec(int host) const;
  // Moves the calling thread's network into `host` (its /dev/shm stays the
  // process's): what that thread makes afterwards, Fast DDS's threads and
  // sockets included, is on that host. Throws std::runtime_error.
  void enter(int host) const;
  std::string address(int host) const;
  // `host`'s name in rig(): h1, h2, ...
  std::string name(int host) const { return "h" + std::to_string(host + 1); }
  // A deployment file naming the hosts, with the network section's
  // defaults (docs/deployment.md, "The network"): what a process on one of
  // them passes as --deployment FILE --host NAME to get a rig's network.
  const std::filesystem::path& rig() const { return rig_; }

 private:
  Hosts() = default;
  void remove() const;
  std::string bridge_, net_;
  std::vector<std::string> names_;
  std::vector<std::filesystem::path> shm_;
  std::filesystem::path rig_;
};

}  // namespace hcosim::services::bench
