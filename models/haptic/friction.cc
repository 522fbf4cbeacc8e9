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

Eigen::Vector3d FrictionCone::slide(const Eigen::Vector3d& proxy, const Eigen::Vector3d& n, const Eigen::Vector3d& h) {
  const double depth = (proxy - h).dot(n);
  const Eigen::Vector3d goal = h + depth * n;  // h on the tangent plane
  const Eigen::Vector3d t = goal - proxy;      // the HIP's tangential offset
  const double offset = t.norm();
  if (depth <= 0) {
    slipping_ = false;
    return h;
  }
  // Stuck while inside the cone of the state it is in: static to break
  // away, dynamic to keep slipping. A proxy left on the rim by the last
  // slip is inside, whatever the rounding of its offset.
  const double cone = (slipping_ ? f_.dynamic_mu : f_.static_mu) * depth;
  if (offset <= cone * (1 + 1e-9)) {
    slipping_ = false;
    return proxy;
  }
  // Slipping: trail the HIP on the dynamic cone's rim.
  slipping_ = true;
  return goal - t * (f_.dynamic_mu * depth / offset);
}

}  // namespace hcosim::models::haptic
