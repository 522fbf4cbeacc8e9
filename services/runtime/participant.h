// One DDS participant per process, with the deployment's QoS profiles.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "adapters/deployment.h"
#include "services/runtime/network.h"
#include "services/runtime/security.h"
#include "services/runtime/topics.h"

namespace hcosim::services::runtime {

// Highest participant id whose ports fit a domain's 250 (7400 + 250 * domain + 11 + 2 * id).
inline constexpr int kMaxParticipantId = 119;

// A domain's first UDP port (the RTPS default mapping) and its last (the
// user unicast port of its highest participant id).
inline constexpr int first_port(int domain) { return 7400 + 250 * domain; }
inline constexpr int last_port(int domain) { return first_port(domain) + 11 + 2 * kMaxParticipantId; }

// Whether a domain's UDP ports (first_port to last_port) meet the
// kernel's ephemeral ports [lo, hi]:
// there another program's socket can hold one of the domain's discovery
// ports and keep its participants from finding each other
// (docs/deployment.md). On Linux's default range, domains 101 to 214.
bool in_ephemeral_range(int domain, int lo, int hi);
// The machine's ephemeral ports (/proc/sys/net/ipv4/ip_local_port_range);
// {0, -1}, an empty range, where that cannot be read.
std::pair<int, int> ephemeral_ports();

// QoS file used when none is named: $HCOSIM_QOS, else the tree's deploy/qos.xml.
std::string default_qos_file();

// Owns the process's DomainParticipant, its publisher and subscriber, and
// one Topic per type used. Destroying it deletes every DDS entity it made,
// which also releases its shared-memory segments.
class Participant {
 public:
  // Loads `qos_file` and joins `domain` under `name` (shown in discovery).
  // Throws std::runtime_error naming the file or the domain on failure.
  // A `listener`, if given, hears discovery from the first moment (and no
  // status: readers' own listeners hear their data, Reader::on_arrival).
  // `lockstep`: see set_lockstep(). `security`, when on, joins with those
  // credentials: only participants of the same CA and permissions match.
  // `network`: how its host reaches a rig's other hosts (network.h).
  Participant(int domain, const std::string& name, const std::string& qos_file = default_qos_file(),
              eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr, bool lockstep = false,
              const Security& security = {}, const Network& network = {});
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // The Topic of type T, registering the type on first use.
  template <class T>
  eprosima::fastdds::dds::Topic* topic() {
    auto it = topics_.find(TopicOf<T>::name);
    if (it != topics_.end()) return it->second;
    return make_topic(TopicOf<T>::name, TopicOf<T>::type_name, new typename TopicOf<T>::PubSub());
  }

  // In lockstep every writer and reader made afterwards is RELIABLE and
  // readers keep kLockstepDepth samples per instance: a step must see every
  // input of the steps before it (docs/cosimulation.md).
  void set_lockstep(bool on) { lockstep_ = on; }
  bool lockstep() const { return lockstep_; }
  static constexpr int kLockstepDepth = 16;

  eprosima::fastdds::dds::DomainParticipant* dds() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }

 private:
  eprosima::fastdds::dds::Topic* make_topic(const char* topic, const char* type,
                                            eprosima::fastdds::dds::TopicDataType* support);

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  bool lockstep_ = false;
};

}  // namespace hcosim::services::runtime
