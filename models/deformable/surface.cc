#include "models/deformable/surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Geometry>

#include "models/deformable/proxy.h"

namespace hcosim::models::deformable {

GridSurface grid_surface(int nx, int ny, int nz) {
  if (nx < 2 || ny < 2 || nz < 2) throw std::invalid_argument("grid_surface: needs at least 2 nodes per side");
  return voxel_surface(models::massspring::box_voxels(nx - 1, ny - 1, nz - 1, 1));
}

GridSurface voxel_surface(const models::massspring::Voxels& voxels) {
  const std::vector<int> mass = voxels.masses();
  GridSurface s;
  std::vector<int> local(mass.size(), -1);
  auto vertex = [&](const int c[3]) {
    const long node = voxels.node(c[0], c[1], c[2]);
    int& v = local[node];
    if (v < 0) v = int(s.nodes.size()), s.nodes.push_back(mass[node]);
    return v;
  };
  const int n[3] = {voxels.cells.x(), voxels.cells.y(), voxels.cells.z()};
  // Squares normal to axis a on side 0 or 1 of a filled cell whose
  // neighbour there is empty; (b, c) is ordered so that b x c points
  // outward, which makes each square's corners counter-clockwise seen
  // from outside.
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      int b = (a + 1) % 3, c = (a + 2) % 3;
      if (side == 0) std::swap(b, c);
      for (int layer = side ? n[a] - 1 : 0; side ? layer >= 0 : layer < n[a]; layer += side ? -1 : 1)
        for (int v = 0; v < n[c]; ++v)
          for (int u = 0; u < n[b]; ++u) {
            int cell[3], out[3];
            cell[a] = layer, cell[b] = u, cell[c] = v;
            std::copy(cell, cell + 3, out);
            out[a] += side ? 1 : -1;
            if (!voxels.is_filled(cell[0], cell[1], cell[2]) || voxels.is_filled(out[0], out[1], out[2])) continue;
            int p[4][3];
            const int du[4] = {0, 1, 1, 0}, dv[4] = {0, 0, 1, 1};
            for (int q = 0; q < 4; ++q) p[q][a] = layer + side, p[q][b] = u + du[q], p[q][c] = v + dv[q];
            const int w[4] = {vertex(p[0]), vertex(p[1]), vertex(p[2]), vertex(p[3])};
            s.triangles.emplace_back(w[0], w[1], w[2]);
            s.triangles.emplace_back(w[0], w[2], w[3]);
          }
    }
  return s;
}

models::massspring::TriangleMesh rounded_box(int subdivisions, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                             double exponent) {
  if (subdivisions < 1) throw std::invalid_argument("rounded_box: subdivisions must be >= 1");
  if (!(exponent >= 2) || !std::isfinite(exponent))
    throw std::invalid_argument("rounded_box: exponent must be finite and >= 2");
  if (!(hi.array() > lo.array()).all() || !lo.allFinite() || !hi.allFinite())
    throw std::invalid_argument("rounded_box: hi must exceed lo on every axis");
  const int k = subdivisions + 1;
  const GridSurface g = grid_surface(k, k, k);
  models::massspring::TriangleMesh m;
  m.triangles = g.triangles;
  m.vertices.resize(3, g.nodes.size());
  const Eigen::Vector3d centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  for (std::size_t v = 0; v < g.nodes.size(); ++v) {
    const int node = g.nodes[v];
    // The grid node on the cube [-1, 1]^3, pushed radially onto the surface.
    const Eigen::Vector3d q =
        Eigen::Vector3d(node % k, (node / k) % k, node / (k * k)) * (2.0 / subdivisions) - Eigen::Vector3d::Ones();
    const double r = std::pow(q.cwiseAbs().array().pow(exponent).sum(), 1 / exponent);
    m.vertices.col(v) = centre + half.cwiseProduct(q / r);
  }
  return m;
}

double height_over(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles,
                   const Eigen::Vector2d& at) {
  double top = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3i& t : triangles) {
    const Eigen::Vector3d a = x.col(t[0]), b = x.col(t[1]), c = x.col(t[2]);
    // Barycentric coordinates of `at` in the triangle's xy projection.
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (det == 0) continue;
    const double u = ((at.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (at.y() - a.y())) / det;
    const double w = ((b.x() - a.x()) * (at.y() - a.y()) - (at.x() - a.x()) * (b.y() - a.y())) / det;
    if (u >= 0 && w >= 0 && u + w <= 1) top = std::max(top, a.z() + u * (b.z() - a.z()) + w * (c.z() - a.z()));
  }
  return top;
}

double depth_inside(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles,
                    const Eigen::Vector3d& q) {
  const MeshProxy mesh(triangles, int(x.cols()));
  const SurfacePoint p = mesh.closest(x, q);
  const double d = (q - mesh.point(x, p)).norm();
  return mesh.behind(x, p, q) ? d : -d;
}

Eigen::Matrix3Xd vertex_normals(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles) {
  Eigen::Matrix3Xd n = Eigen::Matrix3Xd::Zero(3, x.cols());
  for (const Eigen::Vector3i& t : triangles) {
    // Twice the area times the unit normal: larger triangles weigh more.
    const Eigen::Vector3d a = (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0]));
    n.col(t[0]) += a, n.col(t[1]) += a, n.col(t[2]) += a;
  }
  for (int v = 0; v < n.cols(); ++v) {
    const double len = n.col(v).norm();
    if (len > 0 && std::isfinite(len))
      n.col(v) /= len;
    else
      n.col(v) = Eigen::Vector3d::UnitZ();
  }
  return n;
}

}  // namespace hcosim::models::deformable
