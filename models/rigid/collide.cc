#include "models/rigid/collide.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Geometry>

namespace hcosim::models::rigid {

namespace {

struct Box {
  Eigen::Vector3d c;
  Eigen::Matrix3d R;  // columns: the box's axes in world
  double h;           // half-edge
};

Box box(const Body& b) { return {b.x, b.q.toRotationMatrix(), b.size}; }

Eigen::Vector3d corner(const Box& b, int k) {
  return b.c + b.R * (b.h * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
}

// The part [t0, t1] of segment p0 + t (p1 - p0), t in [0, 1], inside box
// b grown by `grow` (Liang and Barsky's slab clipping); false if none.
bool clip(const Box& b, double grow, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double& t0, double& t1) {
  const Eigen::Vector3d a = b.R.transpose() * (p0 - b.c), d = b.R.transpose() * (p1 - p0);
  const double h = b.h + grow;
  t0 = 0, t1 = 1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (std::abs(a[k]) > h) return false;
      continue;
    }
    double u = (-h - a[k]) / d[k], w = (h - a[k]) / d[k];
    if (u > w) std::swap(u, w);
    t0 = std::max(t0, u), t1 = std::min(t1, w);
    if (t0 > t1) return false;
  }
  return true;
}

// The extreme points so far along the four diagonals of the tangent plane.
struct Extremes {
  Eigen::Vector3d dir[4];
  double best[4] = {-1e300, -1e300, -1e300, -1e300};
  Eigen::Vector3d at[4];
  void add(const Eigen::Vector3d& p) {
    for (int k = 0; k < 4; ++k)
      if (p.dot(dir[k]) > best[k]) best[k] = p.dot(dir[k]), at[k] = p;
  }
};

// Adds the midpoints of `from`'s edges inside `into`, each weighted by its
// length inside (plus a little, so that a corner that only touches
// counts), and their ends to the extremes.
void edges_inside(const Box& from, const Box& into, double grow, Eigen::Vector3d& sum, double& weight, Extremes& e) {
  for (int k = 0; k < 8; ++k)
    for (int axis = 0; axis < 3; ++axis) {
      if (k & (1 << axis)) continue;  // each edge once, from its corner with the lower coordinate
      const Eigen::Vector3d p0 = corner(from, k), p1 = corner(from, k | (1 << axis));
      double t0 = 0, t1 = 0;
      if (!clip(into, grow, p0, p1, t0, t1)) continue;
      const double w = (t1 - t0) * 2 * from.h + 1e-6 * from.h;
      sum += w * (p0 + 0.5 * (t0 + t1) * (p1 - p0));
      weight += w;
      e.add(p0 + t0 * (p1 - p0)), e.add(p0 + t1 * (p1 - p0));
    }
}

bool boxes(const Body& a, const Body& b, double gap, Contact& c) {
  const Box A = box(a), B = box(b);
  const Eigen::Vector3d d = B.c - A.c;
  double best = std::numeric_limits<double>::infinity();
  // Each axis's overlap; an edge-edge axis must beat the faces by 5 % to
  // be chosen, so that a face lying on a face keeps its face normal when
  // rounding makes a cross product's overlap equal.
  const auto axis = [&](Eigen::Vector3d L, double bias) {
    const double n = L.norm();
    if (n < 1e-9) return true;  // parallel edges: a face axis covers it
    L /= n;
    const double ra = A.h * (A.R.transpose() * L).cwiseAbs().sum();
    const double rb = B.h * (B.R.transpose() * L).cwiseAbs().sum();
    const double along = d.dot(L), overlap = ra + rb - std::abs(along);
    if (overlap < -gap) return false;
    if (bias * overlap < best)
      best = bias * overlap, c.depth = overlap, c.normal = along >= 0 ? L : Eigen::Vector3d(-L);
    return true;
  };
  for (int i = 0; i < 3; ++i)
    if (!axis(A.R.col(i), 1) || !axis(B.R.col(i), 1)) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!axis(A.R.col(i).cross(B.R.col(j)), 1.05)) return false;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0;
  Extremes e;
  const Eigen::Vector3d t1 = c.normal.unitOrthogonal(), t2 = c.normal.cross(t1);
  e.dir[0] = t1 + t2, e.dir[1] = t1 - t2, e.dir[2] = -t1 + t2, e.dir[3] = -t1 - t2;
  edges_inside(A, B, gap, sum, weight, e);
  edges_inside(B, A, gap, sum, weight, e);
  c.point = weight > 0 ? Eigen::Vector3d(sum / weight) : Eigen::Vector3d(0.5 * (A.c + B.c));
  // The corners, each moved to midway between the surfaces along the
  // normal (as `point` is), once each.
  c.supports = 0;
  for (int k = 0; k < 4 && weight > 0; ++k) {
    const Eigen::Vector3d p = e.at[k] + (c.point - e.at[k]).dot(c.normal) * c.normal;
    bool seen = false;
    for (int j = 0; j < c.supports; ++j) seen = seen || (c.support[std::size_t(j)] - p).norm() < 1e-9 * A.h;
    if (!seen) c.support[std::size_t(c.supports++)] = p;
  }
  return true;
}

// Sphere s against cube k; the normal out of the cube.
bool sphere_cube(const Body& k, const Body& s, double gap, Contact& c) {
  const Nearest n = nearest(k, s.x);
  c.depth = s.size - n.distance;
  if (c.depth < -gap) return false;
  c.normal = n.normal;
  c.point = n.point - 0.5 * c.depth * n.normal;
  return true;
}

}  // namespace

bool collide(const Body& a, const Body& b, double gap, Contact& c) {
  // Bounding spheres apart: no contact (the common case, and cheap).
  const double reach_a = a.shape == Shape::cube ? std::sqrt(3.0) * a.size : a.size;
  const double reach_b = b.shape == Shape::cube ? std::sqrt(3.0) * b.size : b.size;
  if ((b.x - a.x).squaredNorm() > std::pow(reach_a + reach_b + gap, 2)) return false;
  if (a.shape == Shape::sphere && b.shape == Shape::sphere) {
    const Eigen::Vector3d d = b.x - a.x;
    const double r = d.norm();
    c.depth = a.size + b.size - r;
    if (c.depth < -gap) return false;
    c.normal = r > 0 ? Eigen::Vector3d(d / r) : Eigen::Vector3d::UnitZ();
    c.point = a.x + (a.size - 0.5 * c.depth) * c.normal;
    return true;
  }
  if (a.shape == Shape::cube && b.shape == Shape::cube) return boxes(a, b, gap, c);
  if (a.shape == Shape::cube) return sphere_cube(a, b, gap, c);
  if (!sphere_cube(b, a, gap, c)) return false;
  c.normal = -c.normal;
  return true;
}

}  // namespace hcosim::models::rigid
