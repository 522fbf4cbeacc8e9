// Admission checks for samples arriving over DDS: NaN, Inf, absurd values
// and inconsistent sizes are refused before any model sees them.
#pragma once

#include <optional>
#include <string>

#include "idl/clock.h"
#include "idl/haptic.h"
#include "idl/mesh.h"
#include "idl/rigid.h"
#include "idl/status.h"
#include "idl/vision.h"

namespace hcosim::adapters {

// Bounds past which a value is not a measurement but a fault. They are far
// outside any physical haptic AR rig, so they never clip a real sample.
inline constexpr double kMaxDistanceM = 10.0;    // from the marker origin
inline constexpr double kMaxSpeedMps = 100.0;    // stylus or body speed
inline constexpr double kMaxAngularRadps = 1e4;  // body spin
inline constexpr double kMaxForceN = 1000.0;     // any force on the stylus
inline constexpr double kQuatNormTol = 1e-3;     // | |q| - 1 |
inline constexpr double kMaxStiffnessNpm = 1e7;  // contact stiffness
inline constexpr std::size_t kMaxPixels = 4096u * 4096u;

// Each returns nothing when the sample is admissible, otherwise the first
// problem found, naming the field ("position.x is NaN").
std::optional<std::string> validate(const HapticState& s);
std::optional<std::string> validate(const ForceFeedback& s);
std::optional<std::string> validate(const MarkerPose& s);
std::optional<std::string> validate(const CameraFrame& s);
std::optional<std::string> validate(const RigidBodyState& s);
std::optional<std::string> validate(const RigidDivergence& s);
std::optional<std::string> validate(const DeformedMesh& s);
std::optional<std::string> validate(const MeshTopology& s);
std::optional<std::string> validate(const ServiceStatus& s);
std::optional<std::string> validate(const ClockTick& s);
std::optional<std::string> validate(const StepDone& s);

}  // namespace hcosim::adapters
