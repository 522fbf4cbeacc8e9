#include "models/deformable/hybrid_build.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "models/deformable/proxy.h"
#include "models/deformable/surface.h"
#include "models/massspring/quartet.h"

namespace hcosim::models::deformable {

namespace {

// The shape scaled and moved into place, welded.
models::massspring::TriangleMesh placed(const HybridSpec& s) {
  models::massspring::TriangleMesh m = s.shape;
  check_hybrid(m.vertices.cols() >= 4 && m.vertices.allFinite(), "a shape needs at least 4 finite vertices");
  for (const Eigen::Vector3i& t : m.triangles)
    check_hybrid(t.minCoeff() >= 0 && t.maxCoeff() < m.vertices.cols(), "a shape's triangle indexes no vertex");
  const Eigen::Vector3d lo = m.vertices.rowwise().minCoeff(), hi = m.vertices.rowwise().maxCoeff();
  const double longest = (hi - lo).maxCoeff();
  check_hybrid(longest > 0, "a shape needs an extent");
  m.vertices = ((m.vertices.colwise() - 0.5 * (lo + hi)) * (s.size / longest)).colwise() + s.centre;
  models::massspring::weld(m, 1e-9 * s.size);
  try {
    models::massspring::check_closed(m);
  } catch (const std::invalid_argument& e) {
    check_hybrid(false, std::string("shape: ") + e.what());
  }
  return m;
}

// Anchors the masses on the bottom layer of nodes.
void anchor_bottom(const models::massspring::Voxels& v, std::vector<std::uint8_t>& anchored,
                   const Eigen::Matrix3Xd& rest) {
  int count = 0;
  for (int i = 0; i < rest.cols(); ++i) count += anchored[i] = rest(2, i) < v.origin.z() + 0.5 * v.spacing;
  check_hybrid(count >= 3, "the body's lowest layer of nodes holds " + std::to_string(count) +
                               " (3 or more needed): a shape must rest on a flat underside");
}

}  // namespace

Eigen::AlignedBox3d rest_box(const HybridSpec& s) {
  check(s);
  if (s.shape.triangles.empty())
    return {s.centre - Eigen::Vector3d::Constant(0.5 * s.size), s.centre + Eigen::Vector3d::Constant(0.5 * s.size)};
  const models::massspring::TriangleMesh m = placed(s);
  return {m.vertices.rowwise().minCoeff(), m.vertices.rowwise().maxCoeff()};
}

models::massspring::TriangleMesh hybrid_visual(const HybridSpec& s) {
  check(s);
  if (!s.shape.triangles.empty()) return placed(s);
  const Eigen::AlignedBox3d box = rest_box(s);
  return rounded_box(s.visual_subdivisions, box.min(), box.max(), s.visual_exponent);
}

models::massspring::Voxels hybrid_voxels(const HybridSpec& s) {
  check(s);
  const double spacing = s.size / (s.elements - 1);
  if (!s.shape.triangles.empty()) return models::massspring::voxelise(placed(s), spacing);
  const int n = s.elements - 1;
  models::massspring::Voxels v = models::massspring::box_voxels(n, n, n, spacing);
  v.origin = rest_box(s).min();
  return v;
}

ChainLattice hybrid_chains(const HybridSpec& s) {
  const models::massspring::Voxels v = hybrid_voxels(s);
  const std::vector<int> mass = v.masses();
  const Eigen::Array3i n = v.nodes();
  ChainLattice l = make_chain_box(n.x(), n.y(), n.z(), v.spacing, s.chain);
  l.origin = v.origin;
  ChainMaterial hard = s.chain;
  hard.stiffness *= s.stiff_ratio;
  for (double* r : {&hard.stretch, &hard.compress, &hard.shear}) *r /= s.stiff_ratio;
  for (int e = 0; e < l.size(); ++e) {
    l.present[e] = mass[e] >= 0;
    if (stiff_side(s, l.rest(e))) l.material[e] = hard;
    l.anchored[e] = l.present[e] && e < n.x() * n.y();  // the bottom layer, k = 0
  }
  return l;
}

models::massspring::Lattice hybrid_masses(const HybridSpec& s) {
  const models::massspring::Voxels v = hybrid_voxels(s);
  models::massspring::Lattice l = models::massspring::make_from_voxels(v, s.material);
  for (models::massspring::Spring& sp : l.springs)
    if (stiff_side(s, l.rest.col(sp.i)) && stiff_side(s, l.rest.col(sp.j))) sp.k *= s.stiff_ratio;
  if (s.volume > 0) {
    const double modulus = s.volume * s.material.k / v.spacing;
    const std::size_t first = l.quartets.size();
    models::massspring::add_volumes(l, models::massspring::voxel_tetrahedra(v), modulus, 0, s.volume_floor);
    for (std::size_t q = first; q < l.quartets.size(); ++q) {
      models::massspring::Quartet& t = l.quartets[q];
      if (stiff_side(s, l.rest.col(t.i)) && stiff_side(s, l.rest.col(t.j)) && stiff_side(s, l.rest.col(t.k)) &&
          stiff_side(s, l.rest.col(t.l)))
        t.stiffness *= s.stiff_ratio;
    }
  }
  anchor_bottom(v, l.anchored, l.rest);
  return l;
}

models::fem::Mesh hybrid_mesh(const HybridSpec& s) {
  const models::massspring::Voxels v = hybrid_voxels(s);
  models::fem::Mesh m;
  m.rest = models::massspring::make_from_voxels(v, s.material).rest;
  m.tets = models::massspring::voxel_tetrahedra(v);
  m.anchored.assign(m.size(), 0);
  m.scale.assign(m.tets.size(), 1);
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    bool stiff = true;
    for (const int c : m.tets[t]) stiff = stiff && stiff_side(s, m.rest.col(c));
    if (stiff) m.scale[t] = s.stiff_ratio;
  }
  anchor_bottom(v, m.anchored, m.rest);
  return m;
}

namespace {

// The chain element (a grid node) a side's felt force is calibrated at:
// the top element in the middle of that side's half (of the whole top
// when both sides are one), the highest node of column (i, n.y / 2) or of
// the nearest column that has one.
int gain_element(const HybridSpec& spec, const models::massspring::Voxels& voxels, bool stiff) {
  const std::vector<int> mass = voxels.masses();
  const Eigen::Array3i n = voxels.nodes();
  const int i = spec.stiff_ratio == 1 ? n.x() / 2 : stiff ? n.x() - 1 - n.x() / 4 : n.x() / 4;
  int e = -1;
  for (int k = n.z() - 1; k >= 0; --k)
    for (int j = 0; j < n.y(); ++j)
      for (int c = 0; c < n.x(); ++c) {
        const int node = int(voxels.node(c, j, k));
        if (mass[node] < 0) continue;
        const auto off = [&](int m) {
          const int di = m % n.x() - i, dj = m / n.x() % n.y() - n.y() / 2;
          return di * di + dj * dj;
        };
        if (e < 0 || off(node) < off(e)) e = node;
      }
  return e;
}

}  // namespace

std::pair<Eigen::Vector3d, int> find_gain_point(const HybridSpec& spec, const models::massspring::Voxels& voxels,
                                                const SChain& chains, bool stiff) {
  const Eigen::Vector3d p =
      chains.lattice().rest(gain_element(spec, voxels, stiff)) + 0.5 * voxels.spacing * Eigen::Vector3d(1, 1, 0);
  return {p, chains.nearest_surface(p)};
}

Cage map_cage(const HybridSpec& spec, const models::massspring::Voxels& voxels, const models::massspring::Lattice& lat,
              const models::massspring::TriangleMesh& visual) {
  Cage c;
  if (spec.map == VisualMap::trilinear) {
    for (int i = 0; i < lat.size(); ++i) c.masses.push_back(i);
    return c;
  }
  const GridSurface g = voxel_surface(voxels);
  c.masses = g.nodes, c.triangles = g.triangles;
  c.rest.resize(3, c.masses.size());
  for (std::size_t v = 0; v < c.masses.size(); ++v) c.rest.col(v) = lat.rest.col(c.masses[v]);
  if (!spec.shape.triangles.empty()) {
    // A shape's surface lies up to a cell from the cells' boundary, where
    // mean value weights spread a point over much of the cage: the map's
    // cage is moved toward the surface, each node by at most 0.45 of a
    // cell so that no two meet. The map then reads the masses'
    // displacements, which are the same wherever their rest is drawn.
    const MeshProxy shape(visual.triangles, int(visual.vertices.cols()));
    for (int v = 0; v < c.rest.cols(); ++v) {
      const Eigen::Vector3d to =
          shape.point(visual.vertices, shape.closest(visual.vertices, c.rest.col(v))) - c.rest.col(v);
      c.rest.col(v) += to * std::min(1.0, 0.45 * voxels.spacing / std::max(to.norm(), 1e-300));
    }
  }
  return c;
}

Weights map_rows(const HybridSpec& spec, const models::massspring::Voxels& voxels, const Cage& cage,
                 const Eigen::Matrix3Xd& points) {
  if (spec.map == VisualMap::trilinear) {
    const Eigen::Array3i n = voxels.nodes();
    return trilinear_weights(n.x(), n.y(), n.z(), voxels.spacing, voxels.origin, points);
  }
  return mvc_map(spec, cage.rest, cage.triangles, points);
}

Weights mvc_map(const HybridSpec& spec, const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                const Eigen::Matrix3Xd& points) {
  Weights w = mean_value_weights(cage, triangles, points);
  return spec.map == VisualMap::mvc_sparse ? truncate(w, spec.keep) : w;
}

}  // namespace hcosim::models::deformable
