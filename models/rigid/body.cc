#include "models/rigid/body.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::models::rigid {

const char* name(Shape s) { return s == Shape::cube ? "cube" : "sphere"; }

Shape parse_shape(const std::string& s) {
  if (s == "sphere") return Shape::sphere;
  if (s == "cube") return Shape::cube;
  throw std::invalid_argument("rigid: shape must be sphere or cube, got '" + s + "'");
}

void check(const Body& b) {
  if (!(b.size > 0 && std::isfinite(b.size))) throw std::invalid_argument("rigid: body size must be > 0");
  if (!(b.mass > 0 && std::isfinite(b.mass))) throw std::invalid_argument("rigid: body mass must be > 0");
  if (!b.x.allFinite() || !b.v.allFinite() || !b.w.allFinite() || !b.q.coeffs().allFinite())
    throw std::invalid_argument("rigid: body state is not finite");
  if (std::abs(b.q.norm() - 1) > 1e-6) throw std::invalid_argument("rigid: body orientation is not a unit quaternion");
}

double inertia(const Body& b) {
  return b.shape == Shape::sphere ? 0.4 * b.mass * b.size * b.size : b.mass * (2 * b.size) * (2 * b.size) / 6;
}

Nearest nearest(const Body& b, const Eigen::Vector3d& p, double margin) {
  Nearest n;
  const Eigen::Vector3d d = p - b.x;
  if (b.shape == Shape::sphere) {
    const double r = d.norm();
    n.normal = r > 0 ? Eigen::Vector3d(d / r) : Eigen::Vector3d::UnitZ();
    n.distance = r - b.size - margin;
    n.point = b.x + (b.size + margin) * n.normal;
    return n;
  }
  const double h = b.size + margin;
  const Eigen::Matrix3d R = b.q.toRotationMatrix();
  const Eigen::Vector3d local = R.transpose() * d;
  const Eigen::Vector3d clamped = local.cwiseMax(-h).cwiseMin(h);
  Eigen::Vector3d point = clamped, normal;
  if (clamped != local) {
    // Outside: the box point nearest to p.
    const Eigen::Vector3d gap = local - clamped;
    n.distance = gap.norm();
    normal = gap / n.distance;
  } else {
    // Inside: out through the nearest face.
    int axis = 0;
    (h - local.cwiseAbs().array()).minCoeff(&axis);
    const double side = local[axis] >= 0 ? 1 : -1;
    n.distance = -(h - std::abs(local[axis]));
    point[axis] = side * h;
    normal = side * Eigen::Vector3d::Unit(axis);
  }
  n.point = b.x + R * point;
  n.normal = R * normal;
  return n;
}

Eigen::Vector3d momentum(const Body& b) { return b.mass * b.v; }

Eigen::Vector3d angular_momentum(const Body& b) { return b.mass * b.x.cross(b.v) + inertia(b) * b.w; }

double kinetic_energy(const Body& b) { return 0.5 * b.mass * b.v.squaredNorm() + 0.5 * inertia(b) * b.w.squaredNorm(); }

}  // namespace hcosim::models::rigid
