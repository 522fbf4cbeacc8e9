#include "models/haptic/passivity.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hcosim::models::haptic {

PassivityController::PassivityController(double dt, double max_damping, double reservoir)
    : dt_(dt), max_damping_(max_damping), reservoir_(reservoir) {
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("passivity: dt must be finite and > 0");
  if (!(max_damping > 0) || !std::isfinite(max_damping))
    throw std::invalid_argument("passivity: max_damping must be finite and > 0");
  if (!(reservoir > 0) || !std::isfinite(reservoir))
    throw std::invalid_argument("passivity: reservoir must be finite and > 0");
}

Eigen::Vector3d PassivityController::filter(const Eigen::Vector3d& force, const Eigen::Vector3d& v,
                                            const Eigen::Vector3d& applied) {
  // Work the environment received over the last tick: the force held over
  // it against the velocity measured across it (its two ends averaged).
  energy_ = std::min(energy_ - applied.dot(0.5 * (v + last_v_)) * dt_, reservoir_);
  last_v_ = v;
  // Predict this tick at the current velocity; damp the deficit away.
  damping_ = 0;
  const double next = energy_ - force.dot(v) * dt_, v2 = v.squaredNorm();
  if (next >= 0 || v2 < 1e-12) return force;
  damping_ = std::min(-next / (dt_ * v2), max_damping_);
  dissipated_ += damping_ * v2 * dt_;
  return force - damping_ * v;
}

}  // namespace hcosim::models::haptic
