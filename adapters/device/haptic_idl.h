// Conversions between the device's frames and the HapticState and
// ForceFeedback topics.
#pragma once

#include <string>

#include <Eigen/Core>

#include "adapters/device/device.h"
#include "idl/haptic.h"
#include "models/haptic/local_model.h"

namespace hcosim::adapters::device {

inline Eigen::Vector3d from_idl(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

inline Vec3 to_idl(const Eigen::Vector3d& v) {
  Vec3 out;
  out.x(v.x()), out.y(v.y()), out.z(v.z());
  return out;
}

// The HapticState of `frame`, with the force the device output that tick.
HapticState haptic_state(const std::string& device, std::uint64_t seq, const StepStamp& stamp, const Frame& frame,
                         const Eigen::Vector3d& rendered);

// What the stylus feels from one source over a tick, and the local model
// the device renders until the next answer (haptic/local_model.h).
struct Feel {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N, on the stylus, world frame
  bool in_contact = false;
  double depth = 0;                                    // m, >= 0: how far the HIP is inside the source
  double stiffness = 0;                                // N/m, >= 0: the contact's stiffness
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, the HIP the force was computed at
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();  // dF/dx, N/m
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();    // unit, out of the source; zero: none
  double radius = 0;                                   // m, where the expansion holds
};

// How far from the answered HIP a device may trust a contact's local
// model: a few ticks of a fast hand (0.5 m/s for 4 ms).
inline constexpr double kContactModelRadius = 0.002;  // m

// A penalty contact's feel: `force` at `position`, stiffness k along the
// unit `normal` (models::haptic::contact_model), trusted within `radius`.
Feel contact_feel(const Eigen::Vector3d& force, const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                  double k, double depth, double radius);

// The feel where a source has nothing within `clearance` (m) of the HIP at
// `position` for the next haptic::kFreeHorizonS, its own motion included:
// no force, a free-space model of that radius (none if clearance <= 0).
Feel free_feel(const Eigen::Vector3d& position, double clearance);

// Whether a source in real time may leave state `seq` (HIP at `hip`)
// unanswered: its last answer, to state `last_seq`, was a free-space model
// that covers the HIP (models::haptic::covers), given at most half of
// haptic::kFreeHorizonS ago. The device renders that model exactly without
// waiting, and the answers every half horizon keep the source fresh there.
bool answer_covered(const Feel& last, std::uint64_t last_seq, const Eigen::Vector3d& hip, std::uint64_t seq,
                    double servo_dt);

// The answer of `source` to HapticState `seq` of `device`.
ForceFeedback force_feedback(const std::string& source, const std::string& device, std::uint64_t seq,
                             const StepStamp& stamp, const Feel& feel);

// The local model an answer carries.
models::haptic::LocalModel local_model(const ForceFeedback& f);

}  // namespace hcosim::adapters::device
