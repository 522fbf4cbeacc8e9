// The PHANToM Omni as a plant: its published characteristics, its force
// limit, and its stylus held by a hand (the virtual user's arm).
#pragma once

#include <Eigen/Core>

namespace hcosim::models::haptic {

// Published characteristics of the SensAble / 3D Systems PHANToM Omni
// (Touch). The workspace is a box centred on `centre` (world frame).
struct OmniSpec {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();                  // m, world frame
  Eigen::Vector3d workspace = Eigen::Vector3d(0.160, 0.120, 0.070);  // m, full extent
  double max_force = 3.3;                                            // N, peak
  double continuous_force = 0.88;                                    // N, sustained
  double resolution = 0.055e-3;                                      // m, position encoder step
  double max_stiffness = 1000;                                       // N/m, upper end of the nominal 0.5-1 N/mm
  double servo_hz = 1000;                                            // Hz
  double tip_mass = 0.045;                                           // kg, apparent mass at the tip
  double tip_damping = 0.05;                                         // N s/m, back-drive viscous friction
  // N, >= 0: back-drive Coulomb friction (the Omni's data sheet: under
  // 0.26 N). It is what lets a stylus held still rest on one encoder count:
  // with viscous terms alone a contact stiffer than a count's force step
  // over the hand has no resting point between counts, and the reported
  // position, and with it the force, steps between two counts for as long
  // as the press is held.
  double backdrive_friction = 0.1;
};

// Throws std::invalid_argument naming the first non-positive or non-finite field.
void check(const OmniSpec& spec);

// `force` scaled down to at most spec.max_force, direction kept; sets
// *saturated when it had to. Non-finite forces give zero and saturate.
Eigen::Vector3d clamp_force(const OmniSpec& spec, const Eigen::Vector3d& force, bool* saturated);

// The hand holding the stylus: a spring-damper pulling the tip toward the
// hand's target. A light grip by default (Hogan's arm impedance is
// 100-1000 N/m); a stiffer grip damps contact more.
struct Hand {
  double stiffness = 200;  // N/m
  double damping = 2;      // N s/m
};

struct Tip {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  // m, world frame
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // m/s
};

// Advances the tip by dt under the hand pulling toward `target` and the
// device's `force`, held over the step (zero-order hold, as a real servo
// loop does). Hand and back-drive terms are implicit, so any grip is
// stable; the back-drive friction sticks the tip while the rest of the
// forces stay inside it; the workspace's walls stop the tip.
void step_tip(const OmniSpec& spec, const Hand& hand, const Eigen::Vector3d& target, const Eigen::Vector3d& force,
              double dt, Tip& tip);

// `x` rounded to the encoder's resolution, as the device reports it.
Eigen::Vector3d quantize(const OmniSpec& spec, const Eigen::Vector3d& x);

}  // namespace hcosim::models::haptic
