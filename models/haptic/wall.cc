#include "models/haptic/wall.h"

#include <algorithm>

namespace hcosim::models::haptic {

Eigen::Vector3d wall_force(const Wall& w, const Eigen::Vector3d& x, const Eigen::Vector3d& v, double* depth) {
  const double d = (w.point - x).dot(w.normal);
  *depth = std::max(d, 0.0);
  if (d <= 0) return Eigen::Vector3d::Zero();
  return std::max(0.0, w.stiffness * d - w.damping * v.dot(w.normal)) * w.normal;
}

}  // namespace hcosim::models::haptic
