#include "models/rigid/coupling.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::models::rigid {

void check(const CouplingSpec& s) {
  if (!(s.stiffness > 0 && std::isfinite(s.stiffness))) throw std::invalid_argument("coupling: stiffness must be > 0");
  if (!(s.damping >= 0 && std::isfinite(s.damping))) throw std::invalid_argument("coupling: damping must be >= 0");
  if (!(s.max_force > 0 && std::isfinite(s.max_force))) throw std::invalid_argument("coupling: max_force must be > 0");
}

Coupling::Coupling(const CouplingSpec& spec, haptic::Friction f) : spec_(spec), proxy_(f) { check(spec_); }

Touch Coupling::touch(const Body& b, double tip_radius, const Eigen::Vector3d& h, const Eigen::Vector3d& hv,
                      double held_s) {
  if (!hv.allFinite()) throw std::invalid_argument("coupling: HIP velocity is not finite");
  if (!(held_s >= 0 && std::isfinite(held_s))) throw std::invalid_argument("coupling: held_s must be >= 0");
  Touch t;
  t.proxy = proxy_.update(b, tip_radius, h);
  if (!proxy_.in_contact()) return t;
  t.contact = true;
  t.normal = nearest(b, t.proxy, tip_radius).normal;
  t.depth = (t.proxy - h).norm();
  // The damper on the normal approach speed of the body's point at the
  // proxy and the HIP, in proportion to depth; a receding body that would
  // be pulled is let go.
  constexpr double kPerMm = 1e3;  // 1/m: the damping is given per mm of depth
  const double approach = t.normal.dot(point_velocity(b, t.proxy) - hv);
  t.force = spec_.stiffness * (t.proxy - h) + spec_.damping * kPerMm * t.depth * approach * t.normal;
  if (t.force.dot(t.normal) <= 0) {
    t.force.setZero();
  } else if (t.force.norm() > spec_.max_force) {
    t.force *= spec_.max_force / t.force.norm();
    t.clamped = true;
  }
  impulse_ -= held_s * t.force;
  moment_ -= held_s * t.proxy.cross(t.force);
  return t;
}

Wrench Coupling::load(const Body& b, double dt) {
  if (!(dt > 0)) throw std::invalid_argument("coupling: dt must be > 0");
  Wrench w;
  w.force = impulse_ / dt;
  // The moment about the origin less that of the force through the centre.
  w.torque = (moment_ - b.x.cross(impulse_)) / dt;
  impulse_.setZero(), moment_.setZero();
  return w;
}

}  // namespace hcosim::models::rigid
