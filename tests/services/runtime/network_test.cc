// What a host of a rig gives Fast DDS: its address as the only UDP
// interface, every host's address as initial peers (no multicast), or the
// Discovery Server's; no shared memory when the file says udp, and UDP
// beside shared memory leaves this host's readers to it.
#include "services/runtime/network.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <gtest/gtest.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include "services/runtime/participant.h"
#include "services/runtime/transport.h"

namespace hcosim::services::runtime {
namespace {

using eprosima::fastdds::dds::DomainParticipantFactory;
using eprosima::fastdds::dds::DomainParticipantQos;
using eprosima::fastdds::rtps::SharedMemTransportDescriptor;
using eprosima::fastdds::rtps::UDPv4TransportDescriptor;

// Three hosts, the camera's given by its interface (lo), unless `camera` is off.
adapters::Deployment rig(const std::string& network, bool camera = true) {
  const std::string path = "/tmp/hcosim_" + std::to_string(getpid()) + "_rig.yaml";
  std::ofstream(path) << "network: " << network << R"(
hosts:
  - {name: device, address: 10.1.0.1}
  - {name: sim, address: 10.1.0.2, clock: on}
)" << (camera ? "  - {name: camera, interface: lo}\n" : "");
  adapters::Deployment d = adapters::load_deployment(path);
  std::remove(path.c_str());
  return d;
}

// The profile's participant QoS, as Participant starts from.
DomainParticipantQos profile() {
  auto* factory = DomainParticipantFactory::get_instance();
  EXPECT_EQ(factory->load_XML_profiles_file(default_qos_file()), eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
  DomainParticipantQos qos;
  factory->get_participant_qos_from_profile("hcosim_participant", qos);
  return qos;
}

// The UDPv4 descriptor of `qos`, under UdpBesideShm's where it is wrapped.
std::shared_ptr<UDPv4TransportDescriptor> udp_of(const DomainParticipantQos& qos) {
  for (const auto& t : qos.transport().user_transports) {
    if (auto u = std::dynamic_pointer_cast<UDPv4TransportDescriptor>(t)) return u;
    if (auto w = std::dynamic_pointer_cast<UdpBesideShmDescriptor>(t))
      return std::dynamic_pointer_cast<UDPv4TransportDescriptor>(w->low_level_descriptor);
  }
  return nullptr;
}

bool udp_beside_shm(const DomainParticipantQos& qos) {
  for (const auto& t : qos.transport().user_transports)
    if (std::dynamic_pointer_cast<UdpBesideShmDescriptor>(t)) return true;
  return false;
}

bool has_shm(const DomainParticipantQos& qos) {
  for (const auto& t : qos.transport().user_transports)
    if (std::dynamic_pointer_cast<SharedMemTransportDescriptor>(t)) return true;
  return false;
}

TEST(Network, OneMachineKeepsTheProfile) {
  const Network n = network_of(rig("{discovery: peers}", false), "");
  EXPECT_EQ(n.discovery, "multicast");
  DomainParticipantQos qos = profile();
  apply(n, qos);
  EXPECT_TRUE(has_shm(qos));
  EXPECT_TRUE(udp_beside_shm(qos)) << "UDP leaves this host's readers to shared memory";
  ASSERT_TRUE(udp_of(qos));
  EXPECT_TRUE(udp_of(qos)->interfaceWhiteList.empty());
  EXPECT_TRUE(qos.wire_protocol().builtin.initialPeersList.empty());
}

TEST(Network, PeersAreEveryHostsAddressAndTheHostsOwnIsItsOnlyInterface) {
  const Network n = network_of(rig("{discovery: peers, transport: udp, socket_buffer_kib: 512}", false), "sim");
  DomainParticipantQos qos = profile();
  const auto before = udp_of(qos);
  apply(n, qos);
  EXPECT_FALSE(has_shm(qos));
  EXPECT_FALSE(udp_beside_shm(qos)) << "with no shared memory, UDP reaches every reader";
  const auto udp = udp_of(qos);
  ASSERT_TRUE(udp);
  EXPECT_NE(udp, before) << "the profile's own descriptor was changed";
  EXPECT_EQ(udp->interfaceWhiteList, std::vector<std::string>{"10.1.0.2"});
  EXPECT_EQ(udp->receiveBufferSize, 512u * 1024u);
  EXPECT_EQ(udp->sendBufferSize, 512u * 1024u);
  const auto& peers = qos.wire_protocol().builtin.initialPeersList;
  ASSERT_EQ(peers.size(), 2u);
  EXPECT_EQ(peers.begin()->address[15], 1);  // 10.1.0.1, the device: peers in file order
  EXPECT_EQ(qos.wire_protocol().builtin.metatrafficUnicastLocatorList.size(), 1u);
  EXPECT_EQ(udp->maxInitialPeersRange, 16u);
}

// bulk_mbit: a flow controller that lets 10 ms of the cap out each 10 ms,
// and none without it.
TEST(Network, TheBulkCapIsAFlowControllerOfItsRate) {
  DomainParticipantQos qos = profile();
  apply(network_of(rig("{bulk_mbit: 8}", false), "sim"), qos);
  ASSERT_EQ(qos.flow_controllers().size(), 1u);
  const auto& f = *qos.flow_controllers().front();
  EXPECT_STREQ(f.name, kBulkFlow);
  EXPECT_EQ(f.period_ms, 10u);
  EXPECT_EQ(f.max_bytes_per_period, 10000);  // 8 Mbit/s for 10 ms
  DomainParticipantQos none = profile();
  apply(network_of(rig("{}", false), "sim"), none);
  EXPECT_TRUE(none.flow_controllers().empty());
}

TEST(Network, AHostByInterfaceIsThatInterfacesAddressHere) {
  const Network n = network_of(rig("{discovery: multicast}"), "camera");
  EXPECT_EQ(n.address, "127.0.0.1");
  adapters::Deployment d = rig("{discovery: multicast}");
  d.hosts[2].interface = "hcosim_none0";
  EXPECT_THROW(network_of(d, "camera"), std::runtime_error);
}

TEST(Network, ClientsOfTheDiscoveryServerOnTheClocksHost) {
  const Network n = network_of(rig("{discovery: server, server_port: 11900}"), "device");
  EXPECT_EQ(n.server, "10.1.0.2");
  EXPECT_EQ(n.server_port, 11900);
  DomainParticipantQos qos = profile();
  apply(n, qos);
  const auto& dc = qos.wire_protocol().builtin.discovery_config;
  EXPECT_EQ(dc.discoveryProtocol, eprosima::fastrtps::rtps::DiscoveryProtocol_t::CLIENT);
  ASSERT_EQ(dc.m_DiscoveryServers.size(), 1u);
  std::ostringstream prefix;
  prefix << dc.m_DiscoveryServers.front().guidPrefix;
  EXPECT_EQ(prefix.str(), kDiscoveryServerPrefix);
  EXPECT_TRUE(has_shm(qos));
}

}  // namespace
}  // namespace hcosim::services::runtime
