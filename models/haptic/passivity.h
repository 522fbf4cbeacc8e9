// Passivity observer and controller (Hannaford and Ryu 2002) for a device
// in impedance causality: it measures velocity and outputs force. Forces
// from models computed several milliseconds ago, over DDS, make even a
// passive wall generate energy; the observer counts the energy the
// environment has absorbed, and when that goes negative the controller adds
// just enough damping to bring it back to zero.
#pragma once

#include <Eigen/Core>

namespace hcosim::models::haptic {

class PassivityController {
 public:
  // dt: servo period, s (> 0); max_damping: cap on the added damping,
  // N s/m (> 0); reservoir: cap on the energy the observer banks, J (> 0).
  PassivityController(double dt, double max_damping, double reservoir);

  // The force to output this tick for the environment's `force` and the
  // device's measured velocity `v`; `applied` is the force the device
  // really output last tick (after clamping), whose work over the last tick
  // the observer books first.
  Eigen::Vector3d filter(const Eigen::Vector3d& force, const Eigen::Vector3d& v, const Eigen::Vector3d& applied);

  double observed_energy() const { return energy_; }  // J absorbed by the environment so far, >= 0 after filter()
  double damping() const { return damping_; }         // N s/m added this tick
  double dissipated() const { return dissipated_; }   // J dissipated by the controller so far

 private:
  double dt_, max_damping_, reservoir_;
  double energy_ = 0, damping_ = 0, dissipated_ = 0;
  Eigen::Vector3d last_v_ = Eigen::Vector3d::Zero();
};

}  // namespace hcosim::models::haptic
