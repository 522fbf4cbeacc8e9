// The topic contract in C++: each IDL type's topic name and QoS profile.
// docs/topics.md is the prose version of this table; keep them together.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string_view>
#include <tuple>

#include "idl/clockPubSubTypes.h"
#include "idl/hapticPubSubTypes.h"
#include "idl/meshPubSubTypes.h"
#include "idl/rigidPubSubTypes.h"
#include "idl/statusPubSubTypes.h"
#include "idl/visionPubSubTypes.h"

namespace hcosim::services::runtime {

// Fast DDS 2.9's generated type support hashes a key as serialized into a
// buffer it keeps, and CDR skips the alignment padding between key
// members, so the padding held bytes of the key hashed before: an
// instance had a new handle whenever another key had been hashed between
// (ForceFeedback's source then device; MarkerPose's camera then tag). A
// reliable writer's history then kept a sample of an instance that was
// never written again, and every heartbeat carried a GAP from it to the
// newest sample, which a remote reader walks one sequence number at a
// time (docs/cosimulation.md, "A crawl"). This zeroes the buffer first;
// DDS-XTypes' key hash has zero padding too.
template <class Generated>
struct KeyedPubSubType : Generated {
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5 = false) override {
    if (this->m_isGetKeyDefined)
      std::memset(this->m_keyBuffer, 0, std::max<std::size_t>(Generated::type::getKeyMaxCdrSerializedSize(), 16));
    return Generated::getKey(data, handle, force_md5);
  }
};

template <class T>
struct TopicOf;

#define HCOSIM_TOPIC(Type, topic_name, profile)                \
  template <>                                                  \
  struct TopicOf<Type> {                                       \
    using PubSub = KeyedPubSubType<Type##PubSubType>;          \
    static constexpr const char* name = topic_name;            \
    static constexpr const char* type_name = "hcosim::" #Type; \
    static constexpr const char* qos = profile;                \
  }

HCOSIM_TOPIC(HapticState, "HapticState", "control");
HCOSIM_TOPIC(ForceFeedback, "ForceFeedback", "control");
HCOSIM_TOPIC(MarkerPose, "MarkerPose", "state");
HCOSIM_TOPIC(CameraFrame, "CameraFrame", "state");
HCOSIM_TOPIC(RigidBodyState, "RigidBodyState", "state");
HCOSIM_TOPIC(RigidDivergence, "RigidDivergence", "state");
HCOSIM_TOPIC(DeformedMesh, "DeformedMesh", "state");
HCOSIM_TOPIC(MeshTopology, "DeformedMeshTopology", "latched");
HCOSIM_TOPIC(ServiceStatus, "ServiceStatus", "status");
HCOSIM_TOPIC(ClockTick, "ClockTick", "sequence");
HCOSIM_TOPIC(StepDone, "StepDone", "sequence");

#undef HCOSIM_TOPIC

using AllTypes = std::tuple<HapticState, ForceFeedback, MarkerPose, CameraFrame, RigidBodyState, RigidDivergence,
                            DeformedMesh, MeshTopology, ServiceStatus, ClockTick, StepDone>;

// Carries a type to generic lambdas: f(TypeTag<T>{}).
template <class T>
struct TypeTag {
  using type = T;
};

// Calls f(TypeTag<T>{}) for every type of the contract.
template <class F>
void for_each_topic(F&& f) {
  std::apply([&](auto... sample) { (f(TypeTag<decltype(sample)>{}), ...); }, AllTypes{});
}

// Calls f(TypeTag<T>{}) for the type whose topic is `name`; false if none is.
template <class F>
bool with_topic(std::string_view name, F&& f) {
  bool found = false;
  for_each_topic([&](auto tag) {
    using T = typename decltype(tag)::type;
    if (!found && name == TopicOf<T>::name) {
      found = true;
      f(tag);
    }
  });
  return found;
}

}  // namespace hcosim::services::runtime
