// UDP beside shared memory: a reader that announced a shared-memory locator
// of this host gets nothing over UDP; one that announced only UDP (another
// host, another DDS implementation) gets UDP; the reader's selection
// state is as UDP found it; and UDP's receiving threads say what they are.
#include "services/runtime/transport.h"

#include <fastrtps/utils/IPLocator.h>
#include <gtest/gtest.h>
#include <thread>

#include <fastdds/rtps/transport/TransportReceiverInterface.h>
#include <fastdds/rtps/common/LocatorSelector.hpp>

namespace hcosim::services::runtime {
namespace {

using eprosima::fastrtps::ResourceLimitedContainerConfig;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastrtps::rtps::LocatorSelector;
using eprosima::fastrtps::rtps::LocatorSelectorEntry;

Locator_t udp(const char* address, uint32_t port) {
  Locator_t l;
  l.kind = LOCATOR_KIND_UDPv4;
  IPLocator::setIPv4(l, address);
  l.port = port;
  return l;
}

// A reader at `locators`, enabled, its GUID's last byte `id`.
void reader(LocatorSelectorEntry& e, uint8_t id, std::initializer_list<Locator_t> locators) {
  e.remote_guid.guidPrefix.value[11] = id;
  e.remote_guid.entityId.value[3] = 0x07;
  for (const Locator_t& l : locators) e.unicast.push_back(l);
  e.enable(true);
}

TEST(UdpBesideShm, ReadersSharedMemoryReachesGetNoUdp) {
  UdpBesideShm transport(UdpBesideShmDescriptor(std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>()));
  Locator_t shm;
  shm.kind = LOCATOR_KIND_SHM;
  shm.port = 7411;
  LocatorSelectorEntry here(4, 1), there(4, 1), cyclone(4, 1);
  reader(here, 1, {shm, udp("127.0.0.1", 7411)});
  reader(there, 2, {udp("10.1.0.2", 7413)});
  reader(cyclone, 3, {udp("127.0.0.1", 7415)});
  LocatorSelector selector(ResourceLimitedContainerConfig::fixed_size_configuration(3));
  for (LocatorSelectorEntry* e : {&here, &there, &cyclone}) selector.add_entry(e);

  selector.selection_start();
  transport.select_locators(selector);
  EXPECT_FALSE(selector.is_selected(udp("127.0.0.1", 7411)));
  EXPECT_TRUE(here.state.unicast.empty());
  EXPECT_TRUE(selector.is_selected(udp("10.1.0.2", 7413)));
  EXPECT_TRUE(selector.is_selected(udp("127.0.0.1", 7415)));
  EXPECT_EQ(selector.selected_size(), 2u);
  EXPECT_TRUE(here.enabled) << "the reader stays enabled for the other transports and the next send";
  EXPECT_TRUE(there.enabled && cyclone.enabled);

  // A disabled reader stays disabled, shared memory or not.
  here.enable(false);
  selector.selection_start();
  transport.select_locators(selector);
  EXPECT_FALSE(here.enabled);
  EXPECT_EQ(selector.selected_size(), 2u);
}

// Records whether the thread that passes it a datagram says it receives UDP.
struct Told : eprosima::fastdds::rtps::TransportReceiverInterface {
  void OnDataReceived(const eprosima::fastrtps::rtps::octet*, const uint32_t, const Locator_t&,
                      const Locator_t&) override {
    said = receives_udp();
  }
  bool said = false;
};

// A thread that passed a datagram on from UDP says so from then on (the
// Foxglove bridge never rests there); other threads do not.
TEST(UdpBesideShm, ItsReceivingThreadsSaySo) {
  UdpBesideShm transport(UdpBesideShmDescriptor(std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>()));
  Told next;
  bool after = false;
  std::thread receiving([&] {
    const eprosima::fastrtps::rtps::octet datagram[4] = {'R', 'T', 'P', 'S'};
    transport.receive(&next, datagram, 4, udp("127.0.0.1", 7411), udp("127.0.0.1", 7413));
    after = receives_udp();
  });
  receiving.join();
  EXPECT_TRUE(next.said);
  EXPECT_TRUE(after);
  EXPECT_FALSE(receives_udp());
}

}  // namespace
}  // namespace hcosim::services::runtime
