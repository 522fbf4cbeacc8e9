#include "models/haptic/local_model.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::models::haptic {

Eigen::Vector3d evaluate(const LocalModel& m, const Eigen::Vector3d& x) {
  if (!x.allFinite()) throw std::invalid_argument("local model: the position must be finite");
  if (!(m.radius >= 0)) throw std::invalid_argument("local model: the radius must be >= 0");
  Eigen::Vector3d d = x - m.position;
  const double n = d.norm();
  if (n > m.radius) d *= n > 0 ? m.radius / n : 0.0;
  const Eigen::Vector3d f = m.force + m.jacobian * d;
  // A penalty contact pulls nothing: past its surface it has let go.
  if (f.dot(m.normal) < 0) return Eigen::Vector3d::Zero();
  return f;
}

bool covers(const LocalModel& m, const Eigen::Vector3d& x) {
  return m.radius > 0 && m.force.isZero(0) && m.jacobian.isZero(0) && (x - m.position).norm() < m.radius;
}

LocalModel contact_model(const Eigen::Vector3d& force, const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                         double k, double radius) {
  LocalModel m;
  m.force = force;
  m.position = position;
  m.normal = normal;
  m.jacobian = -k * normal * normal.transpose();
  m.radius = radius;
  return m;
}

}  // namespace hcosim::models::haptic
