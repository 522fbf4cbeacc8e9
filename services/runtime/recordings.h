// The recordings a lockstep follower waits for: hcosim up --record's
// participant, whose readers match a service's writers some time after
// the two participants discover each other. A VOLATILE sample written
// before that match is never recorded, so before its first step a
// follower waits until it has heard the hcosim up of every host of the
// run (each one's participant exists before its services start; up says
// how many in $HCOSIM_UPS), then until its writers reach each of those
// that records (Service).
#pragma once

#include <mutex>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include "services/runtime/participant.h"

namespace hcosim::services::runtime {

// The names of hcosim up's participant: recording the run, and not.
inline constexpr char kUpParticipant[] = "hcosim_up";
inline constexpr char kRecordingParticipant[] = "hcosim_up_recording";

// A participant's discovery listener that keeps the hcosim up
// participants on its domain, and which of them record.
class Recordings : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  // How many hcosim ups were discovered and are not gone since.
  int ups() const;
  // The GUID prefixes of those that record.
  std::vector<eprosima::fastrtps::rtps::GuidPrefix_t> prefixes() const;

 private:
  mutable std::mutex m_;
  std::vector<eprosima::fastrtps::rtps::GuidPrefix_t> ups_, recording_;
};

// The topics of `p`'s writers (runtime::Writer's) that have not matched a
// reader in each participant of `peers` yet: what they write now would
// not reach them all.
std::vector<std::string> unreached(const Participant& p,
                                   const std::vector<eprosima::fastrtps::rtps::GuidPrefix_t>& peers);

}  // namespace hcosim::services::runtime
