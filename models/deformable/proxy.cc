#include "models/deformable/proxy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hcosim::models::deformable {

namespace {

void need_proxy(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("mesh proxy: " + what);
}

}  // namespace

Eigen::Vector3d nearest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  // Voronoi regions of the vertices, then of the edges, then the inside
  // (Ericson, Real-Time Collision Detection, 5.1.5).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return {1 - t, t, 0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return {1 - t, 0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - t, t};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) return {1, 0, 0};  // a collapsed triangle: its first vertex
  return {va / sum, vb / sum, vc / sum};
}

MeshProxy::MeshProxy(std::vector<Eigen::Vector3i> triangles, int vertices) : triangles_(std::move(triangles)) {
  need_proxy(!triangles_.empty(), "the mesh has no triangles");
  std::vector<std::vector<int>>& at = incident_;
  at.resize(vertices);
  for (int f = 0; f < faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = triangles_[f][c];
      need_proxy(v >= 0 && v < vertices, "triangle " + std::to_string(f) + " names vertex " + std::to_string(v) +
                                             " of " + std::to_string(vertices));
      at[v].push_back(f);
    }
  ring_.resize(faces());
  for (int f = 0; f < faces(); ++f) {
    std::vector<int>& r = ring_[f];
    for (int c = 0; c < 3; ++c) r.insert(r.end(), at[triangles_[f][c]].begin(), at[triangles_[f][c]].end());
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
}

Eigen::Vector3d MeshProxy::normal(const Eigen::Matrix3Xd& x, int f) const {
  const Eigen::Vector3i& t = triangles_[f];
  const Eigen::Vector3d n = (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0]));
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitZ();
}

Eigen::Vector3d MeshProxy::normal(const Eigen::Matrix3Xd& x, const SurfacePoint& p) const {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const Eigen::Vector3i& t = triangles_[p.face];
  for (int c = 0; c < 3; ++c) {
    if (p.bary[c] == 0) continue;
    for (const int f : incident_[t[c]]) {
      const Eigen::Vector3i& u = triangles_[f];
      n += p.bary[c] * (x.col(u[1]) - x.col(u[0])).cross(x.col(u[2]) - x.col(u[0]));
    }
  }
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : normal(x, p.face);
}

Eigen::Matrix3Xd MeshProxy::grown(const Eigen::Matrix3Xd& x, double r) const {
  Eigen::Matrix3Xd out = x;
  if (r == 0) return out;
  for (int v = 0; v < int(x.cols()); ++v) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (const int f : incident_[std::size_t(v)]) {
      const Eigen::Vector3i& u = triangles_[f];
      n += (x.col(u[1]) - x.col(u[0])).cross(x.col(u[2]) - x.col(u[0]));
    }
    if (n.norm() > 0) out.col(v) += r * n.normalized();
  }
  return out;
}

Eigen::Vector3d MeshProxy::point(const Eigen::Matrix3Xd& x, const SurfacePoint& p) const {
  const Eigen::Vector3i& t = triangles_[p.face];
  return p.bary[0] * x.col(t[0]) + p.bary[1] * x.col(t[1]) + p.bary[2] * x.col(t[2]);
}

SurfacePoint MeshProxy::entry(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                              const std::vector<int>* faces) const {
  SurfacePoint best;
  double first = 2;  // the crossing's share of the way from `from` to `to`
  const int count = faces ? int(faces->size()) : this->faces();
  for (int i = 0; i < count; ++i) {
    const int f = faces ? (*faces)[i] : i;
    const Eigen::Vector3i& t = triangles_[f];
    const Eigen::Vector3d a = x.col(t[0]), e1 = x.col(t[1]) - a, e2 = x.col(t[2]) - a;
    const Eigen::Vector3d area = e1.cross(e2);
    const double len = area.norm();
    if (!(len > 0)) continue;
    // Signed heights over the face's plane: outside before, inside after.
    const Eigen::Vector3d n = area / len;
    const double s0 = (from - a).dot(n), s1 = (to - a).dot(n);
    if (s0 < 0 || s1 >= 0) continue;
    const double u = s0 / (s0 - s1);
    if (u >= first) continue;
    // Where the HIP then is on the face, in barycentric weights.
    Eigen::Vector3d q = from + u * (to - from) - a;
    q -= q.dot(n) * n;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), d1 = q.dot(e1), d2 = q.dot(e2);
    const double det = d11 * d22 - d12 * d12;
    const double b1 = (d22 * d1 - d12 * d2) / det, b2 = (d11 * d2 - d12 * d1) / det;
    constexpr double kEdge = -1e-9;  // a crossing on a shared edge counts for both faces
    if (!(b1 >= kEdge && b2 >= kEdge && 1 - b1 - b2 >= kEdge)) continue;
    first = u;
    best.face = f;
    best.bary = Eigen::Vector3d(1 - b1 - b2, b1, b2).cwiseMax(0);
    best.bary /= best.bary.sum();
  }
  return best;
}

SurfacePoint MeshProxy::closest(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& q) const {
  SurfacePoint best;
  double d = INFINITY;
  for (int f = 0; f < faces(); ++f) {
    const Eigen::Vector3i& t = triangles_[f];
    const Eigen::Vector3d b = nearest_on_triangle(q, x.col(t[0]), x.col(t[1]), x.col(t[2]));
    const double e = (b[0] * x.col(t[0]) + b[1] * x.col(t[1]) + b[2] * x.col(t[2]) - q).squaredNorm();
    if (e < d) d = e, best = {f, b};
  }
  return best;
}

SurfacePoint MeshProxy::nearest(const Eigen::Matrix3Xd& x, SurfacePoint at, const Eigen::Vector3d& q) const {
  auto on = [&](int f, const Eigen::Vector3d& b) {
    const Eigen::Vector3i& t = triangles_[f];
    return Eigen::Vector3d(b[0] * x.col(t[0]) + b[1] * x.col(t[1]) + b[2] * x.col(t[2]));
  };
  // Each walk step moves to a strictly nearer face; a slide of one tick
  // crosses a few faces, the cap only guards against a mesh folded on
  // itself.
  for (int step = 0; step < 256; ++step) {
    SurfacePoint next = at;
    double best = (on(at.face, at.bary) - q).squaredNorm();
    for (const int f : ring_[at.face]) {
      const Eigen::Vector3i& t = triangles_[f];
      const Eigen::Vector3d b = nearest_on_triangle(q, x.col(t[0]), x.col(t[1]), x.col(t[2]));
      const double d = (on(f, b) - q).squaredNorm();
      if (d < best * (1 - 1e-12)) best = d, next = {f, b};
    }
    if (next.face == at.face) return next;
    at = next;
  }
  return at;
}

FaceGrid::FaceGrid(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles, double cell, double margin)
    : cell_(cell) {
  need_proxy(cell > 0 && std::isfinite(cell) && margin >= 0 && std::isfinite(margin),
             "a face grid needs a finite cell > 0 and margin >= 0");
  need_proxy(x.cols() > 0 && x.allFinite(), "a face grid needs finite positions");
  origin_ = x.rowwise().minCoeff().array() - margin;
  const Eigen::Vector3d extent = x.rowwise().maxCoeff().array() + margin - origin_.array();
  for (int c = 0; c < 3; ++c) dims_[c] = std::clamp(int(std::ceil(extent[c] / cell)), 1, 256);
  bins_.resize(std::size_t(dims_.prod()));
  for (int f = 0; f < int(triangles.size()); ++f) {
    Eigen::AlignedBox3d box;
    for (int c = 0; c < 3; ++c) box.extend(x.col(triangles[f][c]));
    const Eigen::Vector3d lo = box.min().array() - margin, hi = box.max().array() + margin;
    Eigen::Vector3i a, b;
    for (int c = 0; c < 3; ++c) {
      a[c] = std::clamp(int(std::floor((lo[c] - origin_[c]) / cell)), 0, dims_[c] - 1);
      b[c] = std::clamp(int(std::floor((hi[c] - origin_[c]) / cell)), 0, dims_[c] - 1);
    }
    for (int k = a.z(); k <= b.z(); ++k)
      for (int j = a.y(); j <= b.y(); ++j)
        for (int i = a.x(); i <= b.x(); ++i) bins_[i + dims_.x() * (j + dims_.y() * k)].push_back(f);
  }
}

void FaceGrid::near(const Eigen::AlignedBox3d& box, std::vector<int>& out) const {
  out.clear();
  Eigen::Vector3i a, b;
  for (int c = 0; c < 3; ++c) {
    const double lo = (box.min()[c] - origin_[c]) / cell_, hi = (box.max()[c] - origin_[c]) / cell_;
    if (!(hi >= 0 && lo < dims_[c])) return;  // outside the grid, or NaN
    a[c] = std::max(0, int(std::floor(lo)));
    b[c] = std::min(dims_[c] - 1, int(std::floor(hi)));
  }
  for (int k = a.z(); k <= b.z(); ++k)
    for (int j = a.y(); j <= b.y(); ++j)
      for (int i = a.x(); i <= b.x(); ++i) {
        const std::vector<int>& bin = bins_[i + dims_.x() * (j + dims_.y() * k)];
        out.insert(out.end(), bin.begin(), bin.end());
      }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace hcosim::models::deformable
