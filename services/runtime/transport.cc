#include "services/runtime/transport.h"

#include <vector>

#include <fastdds/rtps/common/LocatorSelector.hpp>

namespace hcosim::services::runtime {

using eprosima::fastrtps::rtps::LocatorSelector;
using eprosima::fastrtps::rtps::LocatorSelectorEntry;

namespace {
thread_local bool udp_receiver = false;  // receives_udp()
}  // namespace

bool receives_udp() { return udp_receiver; }

void UdpBesideShm::select_locators(LocatorSelector& selector) const {
  // Fast DDS keeps a remote shared-memory locator only when it is this
  // host's and this participant has shared memory too (ProxyDataFilters),
  // so such a reader is reached there. It is hidden from UDP's selection,
  // which processes only enabled entries, and given back after it, under
  // the writer's lock that holds the selector.
  std::vector<LocatorSelectorEntry*> hidden;
  for (LocatorSelectorEntry* e : selector.transport_starts()) {
    if (!e->enabled) continue;
    for (const auto& l : e->unicast)
      if (l.kind == LOCATOR_KIND_SHM) {
        hidden.push_back(e);
        e->enabled = false;
        break;
      }
  }
  low_level_transport_->select_locators(selector);
  for (LocatorSelectorEntry* e : hidden) e->enabled = true;
}

bool UdpBesideShm::send(eprosima::fastrtps::rtps::SenderResource* low, const eprosima::fastrtps::rtps::octet* buffer,
                        uint32_t size, eprosima::fastrtps::rtps::LocatorsIterator* begin,
                        eprosima::fastrtps::rtps::LocatorsIterator* end,
                        const std::chrono::steady_clock::time_point& timeout) {
  return low->send(buffer, size, begin, end, timeout);
}

void UdpBesideShm::receive(eprosima::fastdds::rtps::TransportReceiverInterface* next,
                           const eprosima::fastrtps::rtps::octet* buffer, uint32_t size,
                           const eprosima::fastrtps::rtps::Locator_t& local,
                           const eprosima::fastrtps::rtps::Locator_t& remote) {
  udp_receiver = true;
  next->OnDataReceived(buffer, size, local, remote);
}

}  // namespace hcosim::services::runtime
