#include "services/runtime/network.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/rtps/flowcontrol/FlowControllerDescriptor.hpp>

#include "services/runtime/transport.h"

namespace hcosim::services::runtime {

namespace {

// The IPv4 address of network interface `name` here, or "".
std::string address_of_interface(const std::string& name) {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return "";
  std::string out;
  for (const ifaddrs* i = list; i && out.empty(); i = i->ifa_next)
    if (i->ifa_addr && i->ifa_addr->sa_family == AF_INET && name == i->ifa_name) {
      char text[INET_ADDRSTRLEN] = {};
      inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(i->ifa_addr)->sin_addr, text, sizeof text);
      out = text;
    }
  freeifaddrs(list);
  return out;
}

eprosima::fastrtps::rtps::Locator_t udp_locator(const std::string& address, int port) {
  eprosima::fastrtps::rtps::Locator_t l;
  l.kind = LOCATOR_KIND_UDPv4;
  eprosima::fastrtps::rtps::IPLocator::setIPv4(l, address);
  l.port = std::uint32_t(port);
  return l;
}

}  // namespace

Network network_of(const adapters::Deployment& d, const std::string& host) {
  Network n;
  if (host.empty() || !d.network.defined) return n;
  const adapters::NetworkSpec& spec = d.network;
  n.discovery = spec.discovery;
  n.udp_only = spec.udp_only;
  n.socket_buffer_bytes = spec.socket_buffer_kib * 1024;
  n.bulk_bytes_per_s = spec.bulk_mbit * 1e6 / 8;
  for (const adapters::Host& h : d.hosts) {
    if (spec.discovery == "peers") n.peers.push_back(h.address);
    if (spec.discovery == "server" && h.name == spec.server) n.server = h.address, n.server_port = spec.server_port;
    if (h.name != host) continue;
    n.address = h.address.empty() ? address_of_interface(h.interface) : h.address;
    if (n.address.empty())
      throw std::runtime_error(h.where + ": host '" + h.name + "': interface " + h.interface +
                               " has no IPv4 address on this machine");
  }
  return n;
}

void apply(const Network& n, eprosima::fastdds::dds::DomainParticipantQos& qos) {
  using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
  using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
  auto& transports = qos.transport().user_transports;
  if (n.udp_only)
    transports.erase(std::remove_if(transports.begin(), transports.end(),
                                    [](const auto& t) {
                                      return std::dynamic_pointer_cast<SharedMemTransportDescriptor>(t) != nullptr;
                                    }),
                     transports.end());
  for (auto& t : transports) {
    const auto udp = std::dynamic_pointer_cast<UDPv4TransportDescriptor>(t);
    if (!udp) continue;
    auto mine = std::make_shared<UDPv4TransportDescriptor>(*udp);
    if (!n.address.empty()) mine->interfaceWhiteList = {n.address};
    if (n.socket_buffer_bytes > 0)
      mine->sendBufferSize = mine->receiveBufferSize = std::uint32_t(n.socket_buffer_bytes);
    // Peers are tried at the ports of participant ids 0 to 15 on each host.
    if (n.discovery == "peers") mine->maxInitialPeersRange = 16;
    t = mine;
  }
  // Beside shared memory, UDP leaves this host's readers to it (transport.h).
  const bool shm = std::any_of(transports.begin(), transports.end(), [](const auto& t) {
    return std::dynamic_pointer_cast<SharedMemTransportDescriptor>(t) != nullptr;
  });
  if (shm)
    for (auto& t : transports)
      if (const auto udp = std::dynamic_pointer_cast<UDPv4TransportDescriptor>(t))
        t = std::make_shared<UdpBesideShmDescriptor>(udp);
  if (n.bulk_bytes_per_s > 0) {
    // A 10 ms period: a sample's fragments go out a period's bytes at a
    // time, not as one burst of the whole sample.
    auto bulk = std::make_shared<eprosima::fastdds::rtps::FlowControllerDescriptor>();
    bulk->name = kBulkFlow;
    bulk->period_ms = 10;
    bulk->max_bytes_per_period = std::int32_t(std::max(1500.0, n.bulk_bytes_per_s * 0.010));
    qos.flow_controllers().push_back(bulk);
  }
  auto& builtin = qos.wire_protocol().builtin;
  if (n.discovery == "peers") {
    // Unicast only: the participant listens on its host's address and
    // announces itself to every host's, never to the multicast group.
    for (const std::string& peer : n.peers) builtin.initialPeersList.push_back(udp_locator(peer, 0));
    builtin.metatrafficUnicastLocatorList.push_back(udp_locator(n.address, 0));
  } else if (n.discovery == "server") {
    eprosima::fastdds::rtps::RemoteServerAttributes server;
    std::istringstream(kDiscoveryServerPrefix) >> server.guidPrefix;
    server.metatrafficUnicastLocatorList.push_back(udp_locator(n.server, n.server_port));
    builtin.discovery_config.discoveryProtocol = eprosima::fastrtps::rtps::DiscoveryProtocol_t::CLIENT;
    builtin.discovery_config.m_DiscoveryServers.push_back(server);
  }
}

}  // namespace hcosim::services::runtime
