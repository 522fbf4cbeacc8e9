#include "models/rigid/proxy.h"

#include <stdexcept>

namespace hcosim::models::rigid {

namespace {

// The point of the grown surface that a point p on (or near) the tangent
// plane at the proxy maps to: radially for a sphere; for a cube, p clamped
// to the box, then pushed out to the proxy's face.
Eigen::Vector3d onto_surface(const Body& b, double margin, const Eigen::Vector3d& local, int face) {
  const double h = b.size + margin;
  if (b.shape == Shape::sphere) {
    const double r = local.norm();
    return r > 0 ? Eigen::Vector3d(local * (h / r)) : Eigen::Vector3d(0, 0, h);
  }
  Eigen::Vector3d p = local.cwiseMax(-h).cwiseMin(h);
  p[face % 3] = face < 3 ? h : -h;
  return p;
}

// The cube face (0..2: +x, +y, +z; 3..5: -x, -y, -z) a box point lies on.
int face_of(const Eigen::Vector3d& local) {
  int axis = 0;
  local.cwiseAbs().maxCoeff(&axis);
  return local[axis] >= 0 ? axis : axis + 3;
}

Eigen::Vector3d face_normal(int face) { return (face < 3 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(face % 3); }

}  // namespace

Eigen::Vector3d Proxy::update(const Body& b, double margin, const Eigen::Vector3d& h) {
  if (!h.allFinite()) throw std::invalid_argument("proxy: HIP is not finite");
  const Eigen::Matrix3d R = b.q.toRotationMatrix();
  const Eigen::Vector3d hl = R.transpose() * (h - b.x);
  if (nearest(b, h, margin).distance > 0) {
    contact_ = false, last_ = h;
    cone_.release();
    return h;
  }
  if (!contact_) {
    // Entering: where the HIP's path from its last free position crossed
    // the surface (bisection on the signed distance).
    Eigen::Vector3d out = R.transpose() * (last_ - b.x), in = hl;
    Body at_origin = b;
    at_origin.x.setZero(), at_origin.q.setIdentity();
    if (nearest(at_origin, out, margin).distance <= 0)
      out = nearest(at_origin, in, margin).point;  // no free past: nearest
    for (int k = 0; k < 50; ++k) {
      const Eigen::Vector3d mid = 0.5 * (out + in);
      (nearest(at_origin, mid, margin).distance > 0 ? out : in) = mid;
    }
    local_ = out;
    contact_ = true;
  }
  // Slide on the tangent plane at the proxy toward the HIP as far as
  // friction lets it, then back onto the surface.
  const int face = face_of(local_);
  const Eigen::Vector3d n = b.shape == Shape::sphere ? Eigen::Vector3d(local_.normalized()) : face_normal(face);
  local_ = onto_surface(b, margin, cone_.slide(local_, n, hl), face);
  return b.x + R * local_;
}

}  // namespace hcosim::models::rigid
