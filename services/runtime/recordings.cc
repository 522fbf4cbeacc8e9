#include "services/runtime/recordings.h"

#include <algorithm>

#include <fastdds/dds/publisher/DataWriter.hpp>

#include "services/runtime/endpoint.h"

namespace hcosim::services::runtime {

using eprosima::fastrtps::rtps::GuidPrefix_t;
using eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;

void Recordings::on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*, ParticipantDiscoveryInfo&& info) {
  const std::string name = info.info.m_participantName.to_string();
  if (name != kUpParticipant && name != kRecordingParticipant) return;
  const GuidPrefix_t prefix = info.info.m_guid.guidPrefix;
  const bool found = info.status == ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT;
  const bool gone = info.status == ParticipantDiscoveryInfo::REMOVED_PARTICIPANT ||
                    info.status == ParticipantDiscoveryInfo::DROPPED_PARTICIPANT;
  std::lock_guard<std::mutex> l(m_);
  for (auto* list : {&ups_, name == kRecordingParticipant ? &recording_ : nullptr}) {
    if (!list) continue;
    const auto it = std::find(list->begin(), list->end(), prefix);
    if (found && it == list->end()) list->push_back(prefix);
    if (gone && it != list->end()) list->erase(it);
  }
}

int Recordings::ups() const {
  std::lock_guard<std::mutex> l(m_);
  return int(ups_.size());
}

std::vector<GuidPrefix_t> Recordings::prefixes() const {
  std::lock_guard<std::mutex> l(m_);
  return recording_;
}

std::vector<std::string> unreached(const Participant& p, const std::vector<GuidPrefix_t>& peers) {
  std::vector<std::string> topics;
  std::vector<eprosima::fastdds::dds::DataWriter*> writers;
  p.publisher()->get_datawriters(writers);
  for (eprosima::fastdds::dds::DataWriter* w : writers) {
    // Fast DDS 2.9.1 has no get_matched_subscriptions: a Writer's Matches
    // listener keeps them.
    const auto* m = dynamic_cast<const Matches*>(w->get_listener());
    if (!m) continue;
    std::lock_guard<std::mutex> l(m->m);
    const bool all = std::all_of(peers.begin(), peers.end(), [&](const GuidPrefix_t& peer) {
      return std::any_of(m->readers.begin(), m->readers.end(),
                         [&](const auto& h) { return participant_of(h) == peer; });
    });
    if (!all) topics.push_back(w->get_topic()->get_name());
  }
  return topics;
}

}  // namespace hcosim::services::runtime
