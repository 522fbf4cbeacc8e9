// The UDPv4 transport every hcosim participant uses beside shared memory.
//
// Fast DDS 2.9.1 sends each sample to every locator a reader announces, one
// transport after the other: a reader on the same host announces a
// shared-memory locator and a UDP one, and gets every sample twice (over
// shared memory, then over UDP loopback, dropped there as a duplicate), at
// the cost of a send, a receive thread's wake-up and a parse per sample
// (docs/PERFORMANCE.md, "Same-host samples"). This transport is Fast DDS's
// UDPv4 transport, unchanged, except that it leaves to shared memory every
// reader that announced a shared-memory locator of this host: readers on
// other hosts, and readers of other DDS implementations on this one, still
// get UDP.
#pragma once

#include <memory>

#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>

namespace hcosim::services::runtime {

// Fast DDS's UDPv4 transport that skips readers shared memory reaches.
class UdpBesideShm : public eprosima::fastdds::rtps::ChainingTransport {
 public:
  explicit UdpBesideShm(const eprosima::fastdds::rtps::ChainingTransportDescriptor& d) : ChainingTransport(d) {}

  // The UDPv4 descriptor underneath.
  eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override {
    return low_level_transport_->get_configuration();
  }

  // UDP's selection, for the readers with no shared-memory locator.
  void select_locators(eprosima::fastrtps::rtps::LocatorSelector& selector) const override;

  bool send(eprosima::fastrtps::rtps::SenderResource* low, const eprosima::fastrtps::rtps::octet* buffer, uint32_t size,
            eprosima::fastrtps::rtps::LocatorsIterator* begin, eprosima::fastrtps::rtps::LocatorsIterator* end,
            const std::chrono::steady_clock::time_point& timeout) override;

  void receive(eprosima::fastdds::rtps::TransportReceiverInterface* next, const eprosima::fastrtps::rtps::octet* buffer,
               uint32_t size, const eprosima::fastrtps::rtps::Locator_t& local,
               const eprosima::fastrtps::rtps::Locator_t& remote) override;
};

// Whether the calling thread is one of a UdpBesideShm's receiving
// threads (it has passed a datagram on): one that must not linger in a
// listener, as its socket's kernel buffer holds a few hundred kB.
bool receives_udp();

// The descriptor of a UdpBesideShm over `udp`.
struct UdpBesideShmDescriptor : public eprosima::fastdds::rtps::ChainingTransportDescriptor {
  explicit UdpBesideShmDescriptor(std::shared_ptr<eprosima::fastdds::rtps::UDPv4TransportDescriptor> udp)
      : ChainingTransportDescriptor(std::move(udp)) {}
  eprosima::fastdds::rtps::TransportInterface* create_transport() const override { return new UdpBesideShm(*this); }
};

}  // namespace hcosim::services::runtime
