#include "models/massspring/mesh_lattice.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

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

bool Voxels::is_filled(int i, int j, int k) const {
  return i >= 0 && j >= 0 && k >= 0 && i < cells.x() && j < cells.y() && k < cells.z() && filled[cell(i, j, k)];
}

std::vector<int> Voxels::masses() const {
  const Eigen::Array3i n = nodes();
  std::vector<int> id(std::size_t(n.prod()), -1);
  for (int k = 0; k < cells.z(); ++k)
    for (int j = 0; j < cells.y(); ++j)
      for (int i = 0; i < cells.x(); ++i)
        if (filled[cell(i, j, k)])
          for (int b = 0; b < 8; ++b) id[node(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2 & 1))] = 0;
  int next = 0;
  for (int& m : id)
    if (m == 0) m = next++;
  return id;
}

Voxels box_voxels(int nx, int ny, int nz, double spacing) {
  if (nx < 1 || ny < 1 || nz < 1) throw std::invalid_argument("voxels: a box needs at least one cell per side");
  if (!(spacing > 0) || !std::isfinite(spacing)) throw std::invalid_argument("voxels: spacing must be finite and > 0");
  Voxels v;
  v.spacing = spacing;
  v.cells << nx, ny, nz;
  v.filled.assign(std::size_t(v.cells.prod()), 1);
  return v;
}

Voxels voxelise(TriangleMesh mesh, double spacing) {
  if (!(spacing > 0) || !std::isfinite(spacing)) throw std::invalid_argument("voxels: spacing must be finite and > 0");
  const Eigen::Vector3d lo = mesh.vertices.rowwise().minCoeff(), hi = mesh.vertices.rowwise().maxCoeff();
  weld(mesh, 1e-9 * std::max(1.0, (hi - lo).norm()));
  check_closed(mesh);
  Voxels v;
  v.origin = lo, v.spacing = spacing;
  v.cells = ((hi - lo) / spacing).array().ceil().cast<int>().max(1);
  const long total = long(v.cells[0]) * v.cells[1] * v.cells[2];
  if (total > 50'000'000)
    throw std::invalid_argument("voxels: spacing " + std::to_string(spacing) + " m gives " + std::to_string(total) +
                                " cells; use a coarser spacing");
  v.filled.assign(total, 0);
  // Inside test by parity along +x through each row of cell centres. The
  // ray is nudged by irrational fractions of a cell so it misses edges.
  std::vector<double> hits;
  for (int k = 0; k < v.cells[2]; ++k)
    for (int j = 0; j < v.cells[1]; ++j) {
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
      for (int i = 0; i < v.cells[0]; ++i) {
        const double x = lo.x() + (i + 0.5) * spacing;
        const long crossed = std::lower_bound(hits.begin(), hits.end(), x) - hits.begin();
        v.filled[v.cell(i, j, k)] = crossed % 2;
      }
    }
  if (std::find(v.filled.begin(), v.filled.end(), 1) == v.filled.end())
    throw std::invalid_argument("voxels: no cell of spacing " + std::to_string(spacing) +
                                " m lies inside the mesh; use a finer spacing");
  return v;
}

Lattice make_from_voxels(const Voxels& v, const Material& m, Shear shear) {
  const std::vector<int> id = v.masses();
  const int count = int(std::count_if(id.begin(), id.end(), [](int i) { return i >= 0; }));
  if (count == 0) throw std::invalid_argument("mesh lattice: no cell is filled");
  Lattice l;
  l.rest.resize(3, count);
  const Eigen::Array3i n = v.nodes();
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i)
        if (const int a = id[v.node(i, j, k)]; a >= 0) l.rest.col(a) = v.origin + v.spacing * Eigen::Vector3d(i, j, k);
  l.mass.setConstant(count, m.mass);
  l.anchored.assign(count, 0);
  l.drag = m.drag;
  auto link = [&](int a, int b) { l.springs.push_back({a, b, (l.rest.col(a) - l.rest.col(b)).norm(), m.k, m.b}); };
  // In make_box's order, node by node: a link or face square is there when
  // a filled cell has it.
  auto any = [&](int i, int j, int k, int di, int dj, int dk) {
    // Cells around the segment or square from node (i, j, k), spanning
    // the axes with d = 1: the cells that hold it are those that differ by
    // -1 or 0 along the other axes.
    for (int a = di ? 0 : -1; a <= 0; ++a)
      for (int b = dj ? 0 : -1; b <= 0; ++b)
        for (int c = dk ? 0 : -1; c <= 0; ++c)
          if (v.is_filled(i + a, j + b, k + c)) return true;
    return false;
  };
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const int a = id[v.node(i, j, k)];
        if (a < 0) continue;
        const int p = i + j + k;
        const int x = i + 1 < n.x() ? id[v.node(i + 1, j, k)] : -1, y = j + 1 < n.y() ? id[v.node(i, j + 1, k)] : -1,
                  z = k + 1 < n.z() ? id[v.node(i, j, k + 1)] : -1;
        if (x >= 0 && any(i, j, k, 1, 0, 0)) link(a, x);
        if (y >= 0 && any(i, j, k, 0, 1, 0)) link(a, y);
        if (z >= 0 && any(i, j, k, 0, 0, 1)) link(a, z);
        // One face square with corners a, u, w and uw (opposite a): its diagonal(s).
        auto square = [&](int u, int w, int uw) {
          if (shear == Shear::both || p % 2 == 0) link(a, uw);
          if (shear == Shear::both || p % 2 == 1) link(u, w);
        };
        if (x >= 0 && y >= 0 && any(i, j, k, 1, 1, 0)) square(x, y, id[v.node(i + 1, j + 1, k)]);
        if (x >= 0 && z >= 0 && any(i, j, k, 1, 0, 1)) square(x, z, id[v.node(i + 1, j, k + 1)]);
        if (y >= 0 && z >= 0 && any(i, j, k, 0, 1, 1)) square(y, z, id[v.node(i, j + 1, k + 1)]);
      }
  check(l);
  return l;
}

std::vector<std::array<int, 4>> voxel_tetrahedra(const Voxels& v) {
  const std::vector<int> id = v.masses();
  std::vector<std::array<int, 4>> tets;
  for (int k = 0; k < v.cells.z(); ++k)
    for (int j = 0; j < v.cells.y(); ++j)
      for (int i = 0; i < v.cells.x(); ++i) {
        if (!v.filled[v.cell(i, j, k)]) continue;
        // Corner b (bits x, y, z) of the cell. The central tetrahedron takes
        // the corners of even i + j + k, whose face diagonals the Shear::one
        // springs join; each other corner cuts off a tetrahedron with its
        // three neighbours.
        int c[8];
        for (int b = 0; b < 8; ++b) c[b] = id[v.node(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2 & 1))];
        const int odd = (i + j + k) % 2;  // the central tetrahedron's corners have popcount parity `odd`
        auto parity = [](int b) { return ((b & 1) + (b >> 1 & 1) + (b >> 2 & 1)) % 2; };
        std::array<int, 4> centre{};
        int n = 0;
        for (int b = 0; b < 8; ++b)
          if (parity(b) == odd) centre[n++] = c[b];
        tets.push_back(centre);
        for (int b = 0; b < 8; ++b)
          if (parity(b) != odd) tets.push_back({c[b], c[b ^ 1], c[b ^ 2], c[b ^ 4]});
      }
  return tets;
}

Lattice make_from_mesh(TriangleMesh mesh, double spacing, const Material& m, Shear shear) {
  return make_from_voxels(voxelise(std::move(mesh), spacing), m, shear);
}

}  // namespace hcosim::models::massspring
