#include "models/deformable/mvc.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hcosim::models::deformable {

namespace {

constexpr double kEps = 1e-10;  // relative: below this a point is on the vertex, edge or face
// Relative distance to a face below which a point takes the barycentric
// weights of its projection (off by at most that distance). Nearer, the
// closed formula divides by the sine of a vanishing angle: on the seed's
// visual mesh, whose face centres lie a rounding error off the cage,
// HybridVisualMap.SeedVisualMeshFollowsAffineCageMotionsForEveryMap finds
// points 3.7 cm astray without this.
constexpr double kNear = 1e-7;

// Mean value coordinates of one point, into w (size n, zeroed).
void point_weights(const Eigen::Matrix3Xd& p, const std::vector<Eigen::Vector3i>& tris, const Eigen::Vector3d& x,
                   double scale, Eigen::VectorXd& w) {
  const int n = int(p.cols());
  Eigen::VectorXd d(n);
  Eigen::Matrix3Xd u(3, n);
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d r = p.col(j) - x;
    d[j] = r.norm();
    if (d[j] < kEps * scale) {
      w.setZero();
      w[j] = 1;
      return;
    }
    u.col(j) = r / d[j];
  }
  w.setZero();
  for (const Eigen::Vector3i& t : tris) {
    const Eigen::Vector3d a = p.col(t[0]), e1 = p.col(t[1]) - a, e2 = p.col(t[2]) - a;
    const Eigen::Vector3d normal = e1.cross(e2);
    const double area2 = normal.norm();
    if (!(area2 > 0)) continue;
    const Eigen::Vector3d r = x - a;
    if (std::abs(r.dot(normal)) / area2 > kNear * scale) continue;
    // Barycentric coordinates of the projection onto the face plane.
    const double b1 = r.cross(e2).dot(normal) / (area2 * area2), b2 = e1.cross(r).dot(normal) / (area2 * area2);
    const double b0 = 1 - b1 - b2;
    if (std::min({b0, b1, b2}) < -kEps) continue;
    w[t[0]] = b0, w[t[1]] = b1, w[t[2]] = b2;
    return;
  }
  for (const Eigen::Vector3i& t : tris) {
    double theta[3], c[3], s[3];
    for (int i = 0; i < 3; ++i) {
      // The angle at x between the other two vertices; atan2 keeps it
      // accurate near pi, where the paper's 2 asin(l / 2) loses half the digits.
      const Eigen::Vector3d a = u.col(t[(i + 1) % 3]), b = u.col(t[(i + 2) % 3]);
      theta[i] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
    const double h = (theta[0] + theta[1] + theta[2]) / 2;
    if (M_PI - h < kEps) {
      // On the triangle: its 2-D barycentric coordinates, and nothing else.
      w.setZero();
      for (int i = 0; i < 3; ++i) w[t[i]] = std::sin(theta[i]) * d[t[(i + 2) % 3]] * d[t[(i + 1) % 3]];
      w /= w.sum();
      return;
    }
    const double det = u.col(t[0]).dot(u.col(t[1]).cross(u.col(t[2])));
    const double sign = det < 0 ? -1 : 1;
    bool coplanar = false;
    for (int i = 0; i < 3; ++i) {
      c[i] =
          2 * std::sin(h) * std::sin(h - theta[i]) / (std::sin(theta[(i + 1) % 3]) * std::sin(theta[(i + 2) % 3])) - 1;
      s[i] = sign * std::sqrt(std::max(0.0, 1 - c[i] * c[i]));
      coplanar = coplanar || std::abs(s[i]) <= kEps;
    }
    // In the triangle's plane but outside it: it adds nothing.
    if (coplanar) continue;
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      w[t[i]] += (theta[i] - c[a] * theta[b] - c[b] * theta[a]) / (d[t[i]] * std::sin(theta[a]) * s[b]);
    }
  }
  w /= w.sum();
}

}  // namespace

Weights mean_value_weights(const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& tris,
                           const Eigen::Matrix3Xd& points) {
  const int n = int(cage.cols());
  if (!cage.allFinite()) throw std::invalid_argument("mvc: cage vertices must be finite");
  for (std::size_t k = 0; k < tris.size(); ++k)
    for (int i = 0; i < 3; ++i)
      if (tris[k][i] < 0 || tris[k][i] >= n)
        throw std::invalid_argument("mvc: triangle " + std::to_string(k) + " refers to vertex " +
                                    std::to_string(tris[k][i]) + " of " + std::to_string(n));
  const double scale = n ? (cage.rowwise().maxCoeff() - cage.rowwise().minCoeff()).norm() : 1;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd w(n);
  for (int m = 0; m < int(points.cols()); ++m) {
    if (!points.col(m).allFinite()) throw std::invalid_argument("mvc: point " + std::to_string(m) + " is not finite");
    point_weights(cage, tris, points.col(m), scale, w);
    for (int j = 0; j < n; ++j)
      if (w[j] != 0) trip.emplace_back(m, j, w[j]);
  }
  Weights out(points.cols(), n);
  out.setFromTriplets(trip.begin(), trip.end());
  return out;
}

Weights truncate(const Weights& w, double keep) {
  if (!(keep > 0 && keep <= 1)) throw std::invalid_argument("mvc: keep must be in (0, 1]");
  std::vector<Eigen::Triplet<double>> trip;
  std::vector<std::pair<double, int>> row;
  for (int r = 0; r < w.outerSize(); ++r) {
    row.clear();
    double total = 0;
    for (Weights::InnerIterator it(w, r); it; ++it)
      row.emplace_back(it.value(), int(it.col())), total += std::abs(it.value());
    std::sort(row.begin(), row.end(),
              [](const auto& a, const auto& b) { return std::abs(a.first) > std::abs(b.first); });
    double kept = 0, sum = 0;
    std::size_t k = 0;
    while (k < row.size() && kept < keep * total) kept += std::abs(row[k].first), sum += row[k].first, ++k;
    for (std::size_t i = 0; i < k; ++i) trip.emplace_back(r, row[i].second, row[i].first / sum);
  }
  Weights out(w.rows(), w.cols());
  out.setFromTriplets(trip.begin(), trip.end());
  return out;
}

Weights trilinear_weights(int nx, int ny, int nz, double spacing, const Eigen::Vector3d& origin,
                          const Eigen::Matrix3Xd& points) {
  if (nx < 2 || ny < 2 || nz < 2) throw std::invalid_argument("trilinear: the grid needs at least 2 nodes per side");
  if (!(spacing > 0)) throw std::invalid_argument("trilinear: spacing must be > 0");
  const int dims[3] = {nx, ny, nz};
  std::vector<Eigen::Triplet<double>> trip;
  for (int m = 0; m < int(points.cols()); ++m) {
    if (!points.col(m).allFinite())
      throw std::invalid_argument("trilinear: point " + std::to_string(m) + " is not finite");
    const Eigen::Vector3d g = (points.col(m) - origin) / spacing;
    int cell[3];
    double f[3];
    for (int c = 0; c < 3; ++c) {
      cell[c] = std::clamp(int(std::floor(g[c])), 0, dims[c] - 2);
      f[c] = g[c] - cell[c];
    }
    for (int corner = 0; corner < 8; ++corner) {
      const int b[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
      double wt = 1;
      for (int c = 0; c < 3; ++c) wt *= b[c] ? f[c] : 1 - f[c];
      if (wt != 0) trip.emplace_back(m, (cell[0] + b[0]) + nx * ((cell[1] + b[1]) + ny * (cell[2] + b[2])), wt);
    }
  }
  Weights out(points.cols(), nx * ny * nz);
  out.setFromTriplets(trip.begin(), trip.end());
  return out;
}

Eigen::Matrix3Xd apply(const Weights& w, const Eigen::Matrix3Xd& x) {
  if (x.cols() != w.cols())
    throw std::invalid_argument("mvc: weights for " + std::to_string(w.cols()) + " cage vertices, got " +
                                std::to_string(x.cols()));
  return (w * x.transpose()).transpose();
}

Eigen::Matrix3Xd apply_moved(const ColumnWeights& w, const Eigen::Matrix3Xd& rest_points, const Eigen::Matrix3Xd& u,
                             double tolerance) {
  if (u.cols() != w.cols() || rest_points.cols() != w.rows())
    throw std::invalid_argument("mvc: weights are " + std::to_string(w.rows()) + " x " + std::to_string(w.cols()) +
                                ", got " + std::to_string(rest_points.cols()) + " points and " +
                                std::to_string(u.cols()) + " displacements");
  Eigen::Matrix3Xd out = rest_points;
  double* o = out.data();
  for (int j = 0; j < int(w.outerSize()); ++j) {
    const double ux = u(0, j), uy = u(1, j), uz = u(2, j);
    if (std::abs(ux) <= tolerance && std::abs(uy) <= tolerance && std::abs(uz) <= tolerance) continue;
    for (ColumnWeights::InnerIterator it(w, j); it; ++it) {
      double* p = o + 3 * it.row();
      const double wt = it.value();
      p[0] += wt * ux, p[1] += wt * uy, p[2] += wt * uz;
    }
  }
  return out;
}

}  // namespace hcosim::models::deformable
