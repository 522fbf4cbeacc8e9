#include "models/massspring/quartet.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "models/massspring/mesh_lattice.h"

namespace hcosim::models::massspring {

double dihedral(const Quartet& h, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]) {
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

double volume(const Quartet& t, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]) {
  const Eigen::Vector3d p0 = x.col(t.i), a = x.col(t.j) - p0, b = x.col(t.k) - p0, c = x.col(t.l) - p0;
  g[1] = b.cross(c) / 6;
  g[2] = c.cross(a) / 6;
  g[3] = a.cross(b) / 6;
  g[0] = -(g[1] + g[2] + g[3]);
  return a.dot(g[1]);
}

double measure(const Quartet& q, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]) {
  return q.measure == Measure::angle ? dihedral(q, x, g) : volume(q, x, g);
}

double strain(const Quartet& q, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]) {
  const double d = measure(q, x, g) - q.rest;
  if (q.measure == Measure::angle || d < 0) return d;
  for (int c = 0; c < 4; ++c) g[c].setZero();
  return 0;
}

double quartet_energy(const Quartet& q, const Eigen::Matrix3Xd& x) {
  Eigen::Vector3d g[4];
  const double d = strain(q, x, g);
  return 0.5 * q.stiffness * d * d;
}

double quartet_forces(const Quartet& q, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, Eigen::Vector3d f[4]) {
  Eigen::Vector3d g[4];
  const double d = strain(q, x, g);
  const int c[4] = {q.i, q.j, q.k, q.l};
  double rate = 0;
  if (q.b > 0)
    for (int k = 0; k < 4; ++k) rate += g[k].dot(v.col(c[k]));
  const double load = q.stiffness * d + q.b * rate;
  for (int k = 0; k < 4; ++k) f[k] = -load * g[k];
  return d;
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
    Quartet h{i, j, first.first, other->second.first, 0, 0, 0};
    Eigen::Vector3d g[4];
    h.rest = dihedral(h, l.rest, g);
    const double len2 = (l.rest.col(j) - l.rest.col(i)).squaredNorm();
    // A1 + A2 is half the sum of the doubled areas.
    const double factor = 6 * len2 / (0.5 * (first.second + other->second.second));
    h.stiffness = rigidity * factor;
    h.b = damping * factor;
    l.quartets.push_back(h);
  }
}

void add_volumes(Lattice& l, const std::vector<std::array<int, 4>>& tets, double modulus, double damping,
                 double floor) {
  if (!(modulus >= 0) || !(damping >= 0) || !std::isfinite(modulus + damping))
    throw std::invalid_argument("volumes: modulus and damping must be finite and >= 0");
  if (!(floor > 0 && floor <= 1)) throw std::invalid_argument("volumes: the floor must be in (0, 1]");
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const std::array<int, 4>& c = tets[t];
    const std::string name = "volumes: tetrahedron " + std::to_string(t);
    for (const int i : c)
      if (i < 0 || i >= l.size())
        throw std::invalid_argument(name + " has a corner outside 0.." + std::to_string(l.size() - 1));
    Quartet q{c[0], c[1], c[2], c[3], 0, 0, 0, Measure::volume};
    Eigen::Vector3d g[4];
    double v = volume(q, l.rest, g);
    if (v < 0) std::swap(q.k, q.l), v = -v;
    double edge = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < a; ++b) edge = std::max(edge, (l.rest.col(c[a]) - l.rest.col(c[b])).norm());
    if (!(v > 1e-18 * edge * edge * edge)) throw std::invalid_argument(name + " has no volume at rest");
    q.rest = floor * v;
    q.stiffness = modulus / v;
    q.b = damping / v;
    l.quartets.push_back(q);
  }
}

std::vector<std::array<int, 4>> box_tetrahedra(int nx, int ny, int nz) {
  return voxel_tetrahedra(box_voxels(nx - 1, ny - 1, nz - 1, 1));
}

}  // namespace hcosim::models::massspring
