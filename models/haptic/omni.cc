#include "models/haptic/omni.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hcosim::models::haptic {

void check(const OmniSpec& s) {
  auto need = [](double v, const char* what) {
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("omni: ") + what + " must be finite and > 0");
  };
  if (!s.centre.allFinite()) throw std::invalid_argument("omni: centre must be finite");
  for (int i = 0; i < 3; ++i) need(s.workspace[i], "workspace");
  need(s.max_force, "max_force");
  need(s.continuous_force, "continuous_force");
  need(s.resolution, "resolution");
  need(s.max_stiffness, "max_stiffness");
  need(s.servo_hz, "servo_hz");
  need(s.tip_mass, "tip_mass");
  if (!(s.tip_damping >= 0) || !std::isfinite(s.tip_damping))
    throw std::invalid_argument("omni: tip_damping must be finite and >= 0");
  if (!(s.backdrive_friction >= 0) || !std::isfinite(s.backdrive_friction))
    throw std::invalid_argument("omni: backdrive_friction must be finite and >= 0");
}

Eigen::Vector3d clamp_force(const OmniSpec& spec, const Eigen::Vector3d& f, bool* saturated) {
  *saturated = false;
  if (!f.allFinite()) {
    *saturated = true;
    return Eigen::Vector3d::Zero();
  }
  const double n = f.norm();
  if (n <= spec.max_force) return f;
  *saturated = true;
  return f * (spec.max_force / n);
}

void step_tip(const OmniSpec& spec, const Hand& hand, const Eigen::Vector3d& target, const Eigen::Vector3d& force,
              double dt, Tip& tip) {
  // m (v' - v) / dt = k (target - x - dt v') - (b_hand + b_tip) v' + f + c,
  // with c the friction: |c| <= backdrive_friction, against v', and
  // whatever holds v' = 0 when that is enough.
  const double m = spec.tip_mass, k = hand.stiffness, b = hand.damping + spec.tip_damping;
  Eigen::Vector3d momentum = m * tip.v + dt * (k * (target - tip.x) + force);
  const double stop = dt * spec.backdrive_friction, p = momentum.norm();
  momentum *= p > stop ? 1 - stop / p : 0;
  tip.v = momentum / (m + dt * b + dt * dt * k);
  tip.x += dt * tip.v;
  const Eigen::Vector3d lo = spec.centre - spec.workspace / 2, hi = spec.centre + spec.workspace / 2;
  for (int i = 0; i < 3; ++i)
    if (tip.x[i] < lo[i] || tip.x[i] > hi[i]) tip.x[i] = std::clamp(tip.x[i], lo[i], hi[i]), tip.v[i] = 0;
}

Eigen::Vector3d quantize(const OmniSpec& spec, const Eigen::Vector3d& x) {
  return (x / spec.resolution).array().round().matrix() * spec.resolution;
}

}  // namespace hcosim::models::haptic
