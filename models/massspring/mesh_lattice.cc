#include "models/massspring/mesh_lattice.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace hcosim::models::massspring {
namespace {

[[noreturn]] void fail_at(const std::string& path, int line, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
}

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

}  // namespace

TriangleMesh read_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::vector<Eigen::Vector3d> v;
  TriangleMesh mesh;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream ls(text);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    if (tag == "v") {
      Eigen::Vector3d p;
      if (!(ls >> p.x() >> p.y() >> p.z())) fail_at(path, line, "a vertex needs three numbers");
      if (!p.allFinite()) fail_at(path, line, "vertex coordinate is not finite");
      if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
        fail_at(path, line, "vertex coordinate beyond +-1e6 m: not a mesh in metres");
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<int> poly;
      for (std::string item; ls >> item;) {
        int idx = 0;
        try {
          std::size_t used = 0;
          idx = std::stoi(item, &used);
          if (used < item.size() && item[used] != '/') throw std::invalid_argument(item);
        } catch (const std::exception&) {
          fail_at(path, line, "'" + item + "' is not a vertex index");
        }
        const int resolved = idx < 0 ? int(v.size()) + idx : idx - 1;
        if (idx == 0 || resolved < 0 || resolved >= int(v.size()))
          fail_at(path, line, "vertex index " + std::to_string(idx) + " is outside 1.." + std::to_string(v.size()));
        poly.push_back(resolved);
      }
      if (poly.size() < 3) fail_at(path, line, "a face needs at least three vertices");
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) mesh.triangles.emplace_back(poly[0], poly[k], poly[k + 1]);
    }
  }
  if (mesh.triangles.empty()) throw std::runtime_error(path + ": no faces");
  mesh.vertices.resize(3, v.size());
  for (std::size_t i = 0; i < v.size(); ++i) mesh.vertices.col(i) = v[i];
  return mesh;
}

int weld(TriangleMesh& mesh, double tol) {
  if (!(tol >= 1e-12)) throw std::invalid_argument("weld: tolerance must be at least 1e-12 m");
  // Cells are whole numbers of `tol`: they must fit a long (found by fuzzing).
  if (mesh.vertices.size() && mesh.vertices.cwiseAbs().maxCoeff() / tol > 1e17)
    throw std::invalid_argument("weld: coordinates too large for a tolerance of " + std::to_string(tol) + " m");
  // Vertices are bucketed on a grid of cell `tol`; neighbours are searched
  // in the 27 surrounding cells.
  using Cell = std::array<long, 3>;
  std::map<Cell, std::vector<int>> grid;
  const int n = int(mesh.vertices.cols());
  std::vector<int> to(n);
  std::vector<int> kept;
  auto cell = [tol](const Eigen::Vector3d& p) {
    return Cell{long(std::floor(p.x() / tol)), long(std::floor(p.y() / tol)), long(std::floor(p.z() / tol))};
  };
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = mesh.vertices.col(i);
    const Cell c = cell(p);
    int found = -1;
    for (long dx = -1; dx <= 1 && found < 0; ++dx)
      for (long dy = -1; dy <= 1 && found < 0; ++dy)
        for (long dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (const int k : it->second)
            if ((mesh.vertices.col(kept[k]) - p).norm() <= tol) found = k;
        }
    if (found < 0) {
      found = int(kept.size());
      kept.push_back(i);
      grid[c].push_back(found);
    }
    to[i] = found;
  }
  Eigen::Matrix3Xd out(3, kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) out.col(k) = mesh.vertices.col(kept[k]);
  std::vector<Eigen::Vector3i> tris;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3i r(to[t[0]], to[t[1]], to[t[2]]);
    if (r[0] != r[1] && r[1] != r[2] && r[0] != r[2]) tris.push_back(r);
  }
  mesh.vertices = out;
  mesh.triangles = tris;
  return n - int(kept.size());
}

void check_closed(const TriangleMesh& mesh) {
  std::unordered_map<std::uint64_t, int> uses;
  for (const auto& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) ++uses[edge_key(t[e], t[(e + 1) % 3])];
  for (const auto& [key, count] : uses)
    if (count != 2)
      throw std::invalid_argument("mesh is not closed: edge (" + std::to_string(key >> 32) + ", " +
                                  std::to_string(key & 0xffffffffu) + ") is used by " + std::to_string(count) +
                                  " triangle(s), a closed surface uses each edge twice");
}

Lattice make_from_mesh(TriangleMesh mesh, double spacing, const Material& m, Shear shear) {
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw std::invalid_argument("mesh lattice: spacing must be finite and > 0");
  const Eigen::Vector3d lo = mesh.vertices.rowwise().minCoeff(), hi = mesh.vertices.rowwise().maxCoeff();
  weld(mesh, 1e-9 * std::max(1.0, (hi - lo).norm()));
  check_closed(mesh);
  const Eigen::Array3i cells = ((hi - lo) / spacing).array().ceil().cast<int>().max(1);
  const long total = long(cells[0]) * cells[1] * cells[2];
  if (total > 50'000'000)
    throw std::invalid_argument("mesh lattice: spacing " + std::to_string(spacing) + " m gives " +
                                std::to_string(total) + " cells; use a coarser spacing");
  // Inside test by parity along +x through each row of cell centres. The
  // ray is nudged by irrational fractions of a cell so it misses edges.
  std::vector<std::uint8_t> inside(total, 0);
  auto cell_id = [&](int i, int j, int k) { return i + long(cells[0]) * (j + long(cells[1]) * k); };
  std::vector<double> hits;
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j) {
      const double y = lo.y() + (j + 0.5 + 1.3e-7 * M_SQRT2) * spacing,
                   z = lo.z() + (k + 0.5 + 1.1e-7 * M_PI) * spacing;
      hits.clear();
      for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d a = mesh.vertices.col(t[0]), b = mesh.vertices.col(t[1]), c = mesh.vertices.col(t[2]);
        // Barycentric coordinates of (y, z) in the triangle's yz projection.
        const double det = (b.y() - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (b.z() - a.z());
        if (det == 0) continue;
        const double u = ((y - a.y()) * (c.z() - a.z()) - (c.y() - a.y()) * (z - a.z())) / det;
        const double w = ((b.y() - a.y()) * (z - a.z()) - (y - a.y()) * (b.z() - a.z())) / det;
        if (u < 0 || w < 0 || u + w > 1) continue;
        hits.push_back(a.x() + u * (b.x() - a.x()) + w * (c.x() - a.x()));
      }
      std::sort(hits.begin(), hits.end());
      for (int i = 0; i < cells[0]; ++i) {
        const double x = lo.x() + (i + 0.5) * spacing;
        const long crossed = std::lower_bound(hits.begin(), hits.end(), x) - hits.begin();
        inside[cell_id(i, j, k)] = crossed % 2;
      }
    }
  // Masses at the corners of inside cells, numbered in grid order.
  const Eigen::Array3i corners = cells + 1;
  auto corner_id = [&](int i, int j, int k) { return i + long(corners[0]) * (j + long(corners[1]) * k); };
  std::unordered_map<long, int> node;
  Lattice l;
  std::vector<Eigen::Vector3d> pos;
  auto mass_at = [&](int i, int j, int k) {
    const auto [it, fresh] = node.emplace(corner_id(i, j, k), int(pos.size()));
    if (fresh) pos.push_back(lo + spacing * Eigen::Vector3d(i, j, k));
    return it->second;
  };
  std::unordered_set<std::uint64_t> linked;
  std::vector<std::pair<int, int>> pairs;
  auto link = [&](int a, int b) {
    if (linked.insert(edge_key(a, b)).second) pairs.emplace_back(a, b);
  };
  for (int k = 0; k < cells[2]; ++k)
    for (int j = 0; j < cells[1]; ++j)
      for (int i = 0; i < cells[0]; ++i) {
        if (!inside[cell_id(i, j, k)]) continue;
        int c[2][2][2];
        for (int a = 0; a < 8; ++a)
          c[a & 1][(a >> 1) & 1][a >> 2] = mass_at(i + (a & 1), j + ((a >> 1) & 1), k + (a >> 2));
        for (int p = 0; p < 2; ++p)
          for (int q = 0; q < 2; ++q)
            link(c[0][p][q], c[1][p][q]), link(c[p][0][q], c[p][1][q]), link(c[p][q][0], c[p][q][1]);
        // Six faces; the diagonal choice follows the face corner's parity
        // so that neighbouring cells agree on a shared face.
        auto face = [&](int a00, int a10, int a01, int a11, int parity) {
          if (shear == Shear::both || parity % 2 == 0) link(a00, a11);
          if (shear == Shear::both || parity % 2 == 1) link(a10, a01);
        };
        for (int s = 0; s < 2; ++s) {
          face(c[0][0][s], c[1][0][s], c[0][1][s], c[1][1][s], i + j + k + s);
          face(c[0][s][0], c[1][s][0], c[0][s][1], c[1][s][1], i + j + k + s);
          face(c[s][0][0], c[s][1][0], c[s][0][1], c[s][1][1], i + j + k + s);
        }
      }
  if (pos.empty())
    throw std::invalid_argument("mesh lattice: no cell of spacing " + std::to_string(spacing) +
                                " m lies inside the mesh; use a finer spacing");
  l.rest.resize(3, pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) l.rest.col(i) = pos[i];
  l.mass.setConstant(pos.size(), m.mass);
  l.anchored.assign(pos.size(), 0);
  l.drag = m.drag;
  for (const auto& [a, b] : pairs) l.springs.push_back({a, b, (l.rest.col(a) - l.rest.col(b)).norm(), m.k, m.b});
  check(l);
  return l;
}

}  // namespace hcosim::models::massspring
