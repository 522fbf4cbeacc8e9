// What one process of a rig of several hosts gives Fast DDS to reach the
// others (docs/deployment.md, "The network"): the deployment's network
// section seen from its host.
#pragma once

#include <string>
#include <vector>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "adapters/deployment.h"

namespace hcosim::services::runtime {

struct Network {
  std::string discovery = "multicast";  // multicast, peers or server
  std::vector<std::string> peers;       // peers: every host's address
  std::string server;                   // server: the discovery server's address
  int server_port = 0;                  // and its UDP port
  std::string address;                  // this host's address: UDP only there; "" any interface
  bool udp_only = false;                // no shared-memory transport
  int socket_buffer_bytes = 0;          // UDP send and receive buffers; 0: the system's
  double bulk_bytes_per_s = 0;          // large samples' cap (kBulkFlow); 0: none
};

// The network of a process on `host` of `d`; Fast DDS's default
// (multicast, any interface, shared memory and UDP) for "" (one machine
// runs every service) or a file without a network section. A host given by interface is that
// interface's IPv4 address on this machine. Throws std::runtime_error when
// the interface has none here.
Network network_of(const adapters::Deployment& d, const std::string& host);

// Sets `qos`'s transports and discovery to `n` (copies of the profile's
// transport descriptors, changed).
void apply(const Network& n, eprosima::fastdds::dds::DomainParticipantQos& qos);

// The flow controller that paces a process's large samples (meshes,
// camera frames) under the network's bulk_mbit: Writer sends those
// asynchronously through it, so that they leave room on a slow link for
// the haptic topics, which never wait behind them.
inline constexpr const char* kBulkFlow = "hcosim_bulk";

// The GUID prefix of Fast DDS Discovery Server id 0 (`fastdds discovery -i 0`).
inline constexpr const char* kDiscoveryServerPrefix = "44.53.00.5f.45.50.52.4f.53.49.4d.41";

}  // namespace hcosim::services::runtime
