#include "models/massspring/hinge.h"

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Geometry>

namespace hcosim::models::massspring {

double dihedral(const Hinge& h, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]) {
  const Eigen::Vector3d p0 = x.col(h.i), e = x.col(h.j) - p0, a = x.col(h.k) - p0, b = x.col(h.l) - p0;
  // Twice each triangle's area along its normal.
  const Eigen::Vector3d na = e.cross(a), nb = (b - e).cross(e);
  const double aa = na.squaredNorm(), bb = nb.squaredNorm(), ee = e.squaredNorm();
  if (!(aa > 1e-48) || !(bb > 1e-48)) {
    for (int c = 0; c < 4; ++c) g[c].setZero();
    return h.rest;
  }
  const double len = std::sqrt(ee);
  const double theta = std::atan2(e.dot(na.cross(nb)) / len, na.dot(nb));
  // An opposite corner moved along its triangle's normal turns that
  // triangle about the edge by the distance over its height; the edge's
  // ends share the opposite corners' gradients by where those project onto
  // the edge, so that translations and rotations leave theta alone.
  const Eigen::Vector3d ga = na * (len / aa), gb = nb * (len / bb);
  const double sa = a.dot(e) / ee, sb = b.dot(e) / ee;
  g[0] = (1 - sa) * ga + (1 - sb) * gb;
  g[1] = sa * ga + sb * gb;
  g[2] = -ga;
  g[3] = -gb;
  return theta;
}

double bending_energy(const Hinge& h, const Eigen::Matrix3Xd& x) {
  Eigen::Vector3d g[4];
  const double d = dihedral(h, x, g) - h.rest;
  return 0.5 * h.k_bend * d * d;
}

double hinge_forces(const Hinge& h, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, Eigen::Vector3d f[4]) {
  Eigen::Vector3d g[4];
  const double theta = dihedral(h, x, g);
  const int c[4] = {h.i, h.j, h.k, h.l};
  double rate = 0;
  if (h.b > 0)
    for (int q = 0; q < 4; ++q) rate += g[q].dot(v.col(c[q]));
  const double moment = h.k_bend * (theta - h.rest) + h.b * rate;
  for (int q = 0; q < 4; ++q) f[q] = -moment * g[q];
  return theta - h.rest;
}

void add_hinges(Lattice& l, const std::vector<Eigen::Vector3i>& triangles, double rigidity, double damping) {
  if (!(rigidity >= 0) || !(damping >= 0) || !std::isfinite(rigidity + damping))
    throw std::invalid_argument("hinges: rigidity and damping must be finite and >= 0");
  // Directed edge (i, j) -> (opposite corner, twice the triangle's area).
  std::map<std::pair<int, int>, std::pair<int, double>> edges;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Eigen::Vector3i& c = triangles[t];
    for (int q = 0; q < 3; ++q)
      if (c[q] < 0 || c[q] >= l.size())
        throw std::invalid_argument("hinges: triangle " + std::to_string(t) + " has a corner outside 0.." +
                                    std::to_string(l.size() - 1));
    const double area2 = (l.rest.col(c[1]) - l.rest.col(c[0])).cross(l.rest.col(c[2]) - l.rest.col(c[0])).norm();
    if (!(area2 > 1e-24)) throw std::invalid_argument("hinges: triangle " + std::to_string(t) + " has no area at rest");
    for (int q = 0; q < 3; ++q)
      if (!edges.emplace(std::make_pair(c[q], c[(q + 1) % 3]), std::make_pair(c[(q + 2) % 3], area2)).second)
        throw std::invalid_argument("hinges: edge " + std::to_string(c[q]) + "-" + std::to_string(c[(q + 1) % 3]) +
                                    " runs the same way in two triangles (inconsistent orientation, or a fan)");
  }
  for (const auto& [edge, first] : edges) {
    const auto [i, j] = edge;
    if (i > j) continue;  // each shared edge once, from its first triangle's side
    const auto other = edges.find({j, i});
    if (other == edges.end()) continue;  // a border edge
    Hinge h{i, j, first.first, other->second.first, 0, 0, 0};
    Eigen::Vector3d g[4];
    h.rest = dihedral(h, l.rest, g);
    const double len2 = (l.rest.col(j) - l.rest.col(i)).squaredNorm();
    // A1 + A2 is half the sum of the doubled areas.
    const double factor = 6 * len2 / (0.5 * (first.second + other->second.second));
    h.k_bend = rigidity * factor;
    h.b = damping * factor;
    l.hinges.push_back(h);
  }
}

}  // namespace hcosim::models::massspring
