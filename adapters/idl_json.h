// JSON text of every IDL type: `hcosim echo`, exports and tests.
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

// Field names and nesting follow the IDL exactly; byte sequences (image
// data) are summarised as their length to keep lines readable.
void write_json(Json& j, const Vec3& v);
void write_json(Json& j, const Quat& q);
void write_json(Json& j, const Transform& p);
void write_json(Json& j, const StepStamp& s);
void write_json(Json& j, const HapticState& s);
void write_json(Json& j, const ForceFeedback& s);
void write_json(Json& j, const MarkerPose& s);
void write_json(Json& j, const CameraFrame& s);
void write_json(Json& j, const RigidBodyState& s);
void write_json(Json& j, const RigidDivergence& s);
void write_json(Json& j, const DeformedMesh& s);
void write_json(Json& j, const MeshTopology& s);
void write_json(Json& j, const ServiceStatus& s);
void write_json(Json& j, const ClockTick& s);
void write_json(Json& j, const StepDone& s);

// One sample as a single-line JSON object.
template <class T>
std::string to_json(const T& sample) {
  Json j;
  write_json(j, sample);
  return j.str();
}

}  // namespace hcosim::adapters
