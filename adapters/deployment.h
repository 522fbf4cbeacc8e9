// The deployment file: which services run, on which domain, in which time mode.
// Every key, unit and default: docs/deployment.md.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "adapters/config.h"
#include "adapters/scene.h"

namespace hcosim::adapters {

// Highest domain id that fits Fast DDS's port formula (7400 + 250 * domain).
inline constexpr int kMaxDomain = 232;

// The keys each map of the file may hold, as docs/deployment.md's tables
// list them (a test holds the two to each other).
namespace keys {
inline const std::vector<std::string> kDeployment{"domain", "mode",    "step",  "duration", "security",
                                                  "hosts",  "network", "scene", "services"};
inline const std::vector<std::string> kSecurity{"dir"};
inline const std::vector<std::string> kHost{"name", "address", "interface", "clock"};
inline const std::vector<std::string> kNetwork{"discovery",         "server",   "server_port", "transport",
                                               "socket_buffer_kib", "bulk_mbit"};
inline const std::vector<std::string> kService{"name",    "kind",     "rate", "params", "on_failure",
                                               "objects", "priority", "cpu",  "host"};
}  // namespace keys

enum class Mode { kRealtime, kLockstep };
const char* to_string(Mode m);
Mode parse_mode(const std::string& s);  // throws std::invalid_argument

// What hcosim up does when a service fails (exits non-zero or is killed).
enum class OnFailure {
  kStopAll,  // stop every service and end the run, exit status 1
  kRestart,  // start it again (real time only), up to kMaxRestarts times
  kIgnore,   // let the others run on (real time only); the exit status is still 1
};
constexpr int kMaxRestarts = 3;
// SCHED_FIFO priority of the haptic kinds' haptic threads (haptic, rigid,
// deformable) unless the entry says `priority`: above the normal
// scheduler, below the kernel's own threaded interrupts (50).
constexpr int kHapticPriority = 30;
const char* to_string(OnFailure f);

// One service entry of the deployment.
struct ServiceSpec {
  std::string name;    // unique, [a-z0-9_], at most 31 characters
  std::string kind;    // executable build/bin/hcosim_<kind>
  double rate_hz = 0;  // step rate, Hz, > 0
  YAML::Node params;   // kind-specific; checked by the service itself
  OnFailure on_failure = OnFailure::kStopAll;
  std::vector<std::string> objects;  // scene objects this service serves; empty: every one of its kind
  std::string unneeded;  // why the scene does not need this service ("" when it does): hcosim up does not start it
  // Real-time scheduling of its haptic threads (real time only): SCHED_FIFO
  // priority 1..99, 0 for the normal scheduler; the core to pin to, -1: any.
  int priority = 0;
  int cpu = -1;
  std::string where;  // "FILE:LINE:COL" of its on_failure (else of the entry), for check_policy
  int line = 0;       // 1-based line of the entry in the file
  std::string host;   // the hosts: entry it runs on; "" when the file has no hosts
};

// One machine of the rig (docs/deployment.md, "Several hosts"): every host
// reads the same file and `hcosim up FILE --host NAME` starts its services.
struct Host {
  std::string name;       // unique, [a-z0-9_]
  std::string address;    // its IPv4 address on the rig's network, or ""
  std::string interface;  // or the network interface that has it, or ""
  std::string where;      // "FILE:LINE:COL" of the entry
};

// Whether a service only watches the run (kind foxglove, the live bridge):
// it runs on the wall clock in either mode, and the lockstep clock does
// not wait for it.
bool observes(const ServiceSpec& s);

// Throws ConfigError at the service's entry if its on_failure policy cannot
// hold in `mode`: a lockstep run waits on every follower at every step, so
// a follower can neither be missing nor rejoin.
void check_policy(const ServiceSpec& s, Mode mode);

// How the hosts find each other and what carries their samples
// (docs/deployment.md, "The network"); it applies to the processes of
// `hcosim up --host` when the file has the section.
struct NetworkSpec {
  bool defined = false;                 // the file has a network section
  std::string discovery = "multicast";  // multicast, peers (every host's address), or server
  std::string server;                   // discovery server: the host that runs it (default: the clock's)
  int server_port = 11811;              // its UDP port
  bool udp_only = false;                // transport udp: no shared memory, even between one host's processes
  int socket_buffer_kib = 4096;         // UDP sockets' send and receive buffers, KiB (0: the system's)
  double bulk_mbit = 0;                 // each process's large samples sent at most this fast, Mbit/s (0: no cap)
};

struct Deployment {
  std::string file;
  Scene scene;
  int domain = 0;  // DDS domain id, 0..232
  Mode mode = Mode::kRealtime;
  double step_s = 0.001;       // base step, s: lockstep tick length
  double duration_s = 0;       // s of simulated time (lockstep) or wall time; 0 = until stopped
  std::string security;        // DDS Security credentials folder, from the file's folder; "" = off
  std::string security_where;  // "FILE:LINE:COL" of its section, for errors about it
  std::vector<Host> hosts;     // empty: one host, today's
  std::string clock_host;      // the host whose hcosim up runs the lockstep clock; "" without hosts
  std::string hosts_where;     // "FILE:LINE:COL" of 'hosts' (1:1 when absent), for errors about them
  NetworkSpec network;
  std::vector<ServiceSpec> services;
  std::string services_where;  // "FILE:LINE:COL" of 'services' (1:1 when absent), for errors about them
};

// The services `hcosim up --host NAME` starts: those placed on that host,
// in file order. Throws ConfigError naming the file when it has no hosts
// or no such host.
std::vector<const ServiceSpec*> services_on(const Deployment& d, const std::string& host);

// Reads and validates a whole deployment file. Throws ConfigError on the
// first problem, naming FILE:LINE:COL.
Deployment load_deployment(const std::string& path);

// One object that answers a haptic device: a scene object (or a body or
// object in a service's own params) of a rigid or deformable service that
// `hcosim up` starts and whose `device` param names that device.
struct ForceSource {
  std::string object;   // ForceFeedback.source
  std::string service;  // the service answering for it
  double rate_hz = 0;   // that service's rate
};
// Every source answering `device` in `d`, in file order.
std::vector<ForceSource> force_sources(const Deployment& d, const std::string& device);

}  // namespace hcosim::adapters
