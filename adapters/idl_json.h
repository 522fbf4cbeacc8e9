// Every IDL type as JSON: `hcosim echo`, exports and tests.
#pragma once

#include <string>

#include "adapters/json.h"
#include "idl/clock.h"
#include "idl/haptic.h"
#include "idl/mesh.h"
#include "idl/rigid.h"
#include "idl/status.h"
#include "idl/vision.h"

namespace hcosim::adapters {

// Field names, order and nesting follow the IDL exactly; byte sequences
// (image data) are summarised as their length (`data_bytes`) to keep
// lines readable.
Json json_of(const Vec3& v);
Json json_of(const Quat& q);
Json json_of(const Transform& p);
Json json_of(const StepStamp& s);
Json json_of(const HapticState& s);
Json json_of(const ForceFeedback& s);
Json json_of(const MarkerPose& s);
Json json_of(const CameraFrame& s);
Json json_of(const RigidBodyState& s);
Json json_of(const RigidDivergence& s);
Json json_of(const DeformedMesh& s);
Json json_of(const MeshTopology& s);
Json json_of(const ServiceStatus& s);
Json json_of(const ClockTick& s);
Json json_of(const StepDone& s);

// One sample as a single-line JSON object.
template <class T>
std::string to_json(const T& sample) {
  return json_line(json_of(sample));
}

}  // namespace hcosim::adapters
