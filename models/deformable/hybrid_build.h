// Building the hybrid model from its spec (001 §II): the body at rest,
// its visual mesh, the cells its lattices stand on, the S-Chain lattice,
// the behavior model's lattice or FEM mesh, the visual map's cage and
// rows, and the points where the force felt is calibrated.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "models/deformable/hybrid_spec.h"
#include "models/deformable/mvc.h"
#include "models/deformable/schain.h"
#include "models/fem/corotational.h"
#include "models/massspring/lattice.h"
#include "models/massspring/mesh_lattice.h"

namespace hcosim::models::deformable {

// The body at rest: its box (m, world), its visual mesh (the rounded cube,
// or the placed shape), and the cells its lattices stand on.
Eigen::AlignedBox3d rest_box(const HybridSpec& spec);
models::massspring::TriangleMesh hybrid_visual(const HybridSpec& spec);
models::massspring::Voxels hybrid_voxels(const HybridSpec& spec);

// The chain lattice (an element at every node of the cells' grid, present
// where a mass is) and the behavior lattice of `spec` (masses numbered as
// Voxels::masses: for the cube, element e of one is mass e of the other).
ChainLattice hybrid_chains(const HybridSpec& spec);
models::massspring::Lattice hybrid_masses(const HybridSpec& spec);
// The FEM behavior model's mesh: the lattice's nodes and anchors, five
// tetrahedra to a cell, stiff_ratio in the stiff side's.
models::fem::Mesh hybrid_mesh(const HybridSpec& spec);

// The visual map's cage: the masses it reads, where their rest is drawn
// for its weights, and its triangles (empty for the trilinear map, whose
// cage is every mass where it is).
struct Cage {
  std::vector<int> masses;
  Eigen::Matrix3Xd rest;
  std::vector<Eigen::Vector3i> triangles;
};
Cage map_cage(const HybridSpec& spec, const models::massspring::Voxels& voxels,
              const models::massspring::Lattice& lattice, const models::massspring::TriangleMesh& visual);

// The map's rows for `points` (visual rest points, 3 x m): what Hybrid's
// map holds for them.
Weights map_rows(const HybridSpec& spec, const models::massspring::Voxels& voxels, const Cage& cage,
                 const Eigen::Matrix3Xd& points);

// The visual map of mean value weights (truncated for mvc_sparse) from the
// cage's rest positions (3 x n), its triangles and the visual rest points
// (3 x m): the slow part of building a Hybrid (about a second at seed
// scale). It depends on nothing else, so a service may keep it on disk.
Weights mvc_map(const HybridSpec& spec, const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                const Eigen::Matrix3Xd& points);
using MapSource = std::function<Weights(const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                                        const Eigen::Matrix3Xd& points)>;

// A side's gain point (rest, world), where its force felt is calibrated
// (force_gain), and the chain element touch() takes there: the middle of a
// top cell's face beside the side's middle column (the soft side's is the
// whole top's middle without a stiff_ratio), where a press spreads over
// four masses, not onto one (under which the lattice stiffens fastest
// with depth).
std::pair<Eigen::Vector3d, int> find_gain_point(const HybridSpec& spec, const models::massspring::Voxels& voxels,
                                                const SChain& chains, bool stiff);

}  // namespace hcosim::models::deformable
