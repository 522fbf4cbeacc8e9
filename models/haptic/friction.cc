#include "models/haptic/friction.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hcosim::models::haptic {

void check(const Friction& f) {
  for (const auto& [name, mu] : {std::pair{"static", f.static_mu}, std::pair{"dynamic", f.dynamic_mu}})
    if (!std::isfinite(mu) || mu < 0)
      throw std::invalid_argument(std::string("friction: the ") + name + " coefficient must be finite and >= 0");
  if (f.dynamic_mu > f.static_mu)
    throw std::invalid_argument("friction: the dynamic coefficient must not exceed the static one");
}

FrictionCone::FrictionCone(Friction f) : f_(f) { check(f_); }

FrictionCone::Grip FrictionCone::grip(const Eigen::Vector3d& force, const Eigen::Vector3d& n) {
  const double push = force.dot(n);
  const Eigen::Vector3d t = force - push * n;
  const double pull = t.norm();
  if (push <= 0) {
    slipping_ = false;
    return {force, 1};
  }
  // Stuck while inside the cone of the state it is in: static to break
  // away, dynamic to keep slipping. A force left on the rim by the last
  // slip is inside, whatever its rounding.
  const double cone = (slipping_ ? f_.dynamic_mu : f_.static_mu) * push;
  if (pull <= cone * (1 + 1e-9)) {
    slipping_ = false;
    return {force, 1};
  }
  // Slipping: the force on the dynamic cone's rim.
  slipping_ = true;
  const double keep = f_.dynamic_mu * push / pull;
  return {push * n + keep * t, keep};
}

Eigen::Vector3d FrictionCone::slide(const Eigen::Vector3d& proxy, const Eigen::Vector3d& n, const Eigen::Vector3d& h) {
  const double depth = (proxy - h).dot(n);
  if (depth <= 0) {
    slipping_ = false;
    return h;
  }
  // A unit spring's force; the proxy keeps the share of its offset that
  // leaves that force inside the cone.
  const Eigen::Vector3d goal = h + depth * n;  // h on the tangent plane
  return goal + grip(proxy - h, n).keep * (proxy - goal);
}

}  // namespace hcosim::models::haptic
