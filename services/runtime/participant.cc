#include "services/runtime/participant.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

namespace hcosim::services::runtime {

using namespace eprosima::fastdds::dds;

bool in_ephemeral_range(int domain, int lo, int hi) { return first_port(domain) <= hi && last_port(domain) >= lo; }

std::pair<int, int> ephemeral_ports() {
  std::ifstream in("/proc/sys/net/ipv4/ip_local_port_range");
  int lo = 0, hi = -1;
  if (!(in >> lo >> hi)) return {0, -1};
  return {lo, hi};
}

std::string default_qos_file() {
  if (const char* env = std::getenv("HCOSIM_QOS"); env && *env) return env;
  return HCOSIM_DEFAULT_QOS_FILE;
}

Participant::Participant(int domain, const std::string& name, const std::string& qos_file,
                         DomainParticipantListener* listener, bool lockstep, const Security& security,
                         const Network& network)
    : lockstep_(lockstep) {
  if (domain < 0 || domain > adapters::kMaxDomain)
    throw std::runtime_error("domain id " + std::to_string(domain) + " is outside 0.." +
                             std::to_string(adapters::kMaxDomain));
  if (!std::ifstream(qos_file)) throw std::runtime_error("QoS profiles file " + qos_file + " cannot be read");
  auto* factory = DomainParticipantFactory::get_instance();
  // Loading the same file twice in one process is harmless: profiles are keyed by name.
  if (factory->load_XML_profiles_file(qos_file) != ReturnCode_t::RETCODE_OK)
    throw std::runtime_error("QoS profiles file " + qos_file + " does not parse (Fast DDS 2.9 XML)");

  DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile("hcosim_participant", qos) != ReturnCode_t::RETCODE_OK)
    throw std::runtime_error(qos_file + " has no participant profile 'hcosim_participant'");
  qos.name(name);
  // hcosim up gives a restarted service a participant id (docs/deployment.md).
  if (const char* id = std::getenv("HCOSIM_PARTICIPANT_ID"); id && *id) {
    char* end = nullptr;
    const long v = std::strtol(id, &end, 10);
    if (*end != '\0' || v < 0 || v > kMaxParticipantId)
      throw std::runtime_error("HCOSIM_PARTICIPANT_ID must be a whole number in 0.." +
                               std::to_string(kMaxParticipantId) + ", not '" + id + "'");
    qos.wire_protocol().participant_id = int32_t(v);
  }
  add_security(security, qos);
  apply(network, qos);
  // Discovery only: a participant listener enabled for data_on_readers would
  // take every reader's data_available away from the reader's own listener.
  participant_ = factory->create_participant(domain, qos, listener, StatusMask::none());
  if (!participant_ && security.on())
    throw std::runtime_error("cannot create a DDS participant on domain " + std::to_string(domain) +
                             " with DDS Security as '" + security.identity + "' (credentials " + security.dir +
                             "): Fast DDS refused them, its log above says why");
  if (!participant_) throw std::runtime_error("cannot create a DDS participant on domain " + std::to_string(domain));
  publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) {
    participant_->delete_contained_entities();
    factory->delete_participant(participant_);
    throw std::runtime_error("cannot create a publisher and subscriber on domain " + std::to_string(domain));
  }
}

Participant::~Participant() {
  participant_->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

Topic* Participant::make_topic(const char* topic, const char* type, TopicDataType* support) {
  TypeSupport ts(support);
  if (ts.register_type(participant_, type) != ReturnCode_t::RETCODE_OK)
    throw std::runtime_error(std::string("cannot register type ") + type);
  Topic* t = participant_->create_topic(topic, type, TOPIC_QOS_DEFAULT);
  if (!t) throw std::runtime_error(std::string("cannot create topic ") + topic);
  topics_.emplace(topic, t);
  return t;
}

}  // namespace hcosim::services::runtime
