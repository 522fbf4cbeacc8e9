// Lattices for organ-like objects (001 Fig 9): a closed triangle mesh,
// read from OBJ, voxelised into the cells of a grid that fill its inside,
// and the lattices that stand on those cells.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/massspring/lattice.h"

namespace hcosim::models::massspring {

struct TriangleMesh {
  Eigen::Matrix3Xd vertices;               // m
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside
};

// Largest |coordinate| read_obj accepts, m.
inline constexpr double kMaxCoordinate = 1e6;

// Reads the `v` and `f` records of a Wavefront OBJ file (polygons are fanned
// into triangles; `f a/b/c` and negative indices are understood; other
// records are ignored). Throws std::runtime_error as "PATH:LINE: problem".
TriangleMesh read_obj(const std::string& path);

// Merges vertices closer than `tolerance` (m, >= 1e-12) and drops the
// triangles that collapse; returns how many vertices were merged. Throws
// std::invalid_argument for a smaller tolerance or coordinates over 1e17
// tolerances.
int weld(TriangleMesh& mesh, double tolerance);

// Throws std::invalid_argument unless every edge is shared by exactly two
// triangles (a closed, manifold surface), naming an offending edge.
void check_closed(const TriangleMesh& mesh);

// The filled cells of a grid of cubes, `spacing` on a side, from `origin`
// (the corner of cell 0). Its nodes are the cells' corners, node
// i + (cells.x + 1) (j + (cells.y + 1) k); a lattice on it has a mass at
// each node that is a corner of a filled cell, numbered in node order.
struct Voxels {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // m
  double spacing = 0.01;                             // m
  Eigen::Array3i cells = Eigen::Array3i::Ones();     // per axis
  std::vector<std::uint8_t> filled;                  // per cell, i + cells.x (j + cells.y k)

  Eigen::Array3i nodes() const { return cells + 1; }
  long cell(int i, int j, int k) const { return i + long(cells.x()) * (j + long(cells.y()) * k); }
  long node(int i, int j, int k) const { return i + long(cells.x() + 1) * (j + long(cells.y() + 1) * k); }
  bool is_filled(int i, int j, int k) const;  // false outside the grid
  // Per node, its mass's index, or -1 where no filled cell has it as a corner.
  std::vector<int> masses() const;
};

// Every cell filled: the box of cells.x x cells.y x cells.z cells, origin 0.
// Throws std::invalid_argument for a side under one cell or a bad spacing.
Voxels box_voxels(int nx, int ny, int nz, double spacing);

// The cells of a grid of `spacing`, from the corner of mesh's box, whose
// centres lie inside `mesh` (parity of crossings along +x). Welds and
// checks the mesh first. Throws std::invalid_argument for a bad spacing, an
// open mesh, over 5 10^7 cells, or no cell filled.
Voxels voxelise(TriangleMesh mesh, double spacing);

// Box lattice (make_box's springs, which it equals on box_voxels) on the
// filled cells: masses at their corners, numbered as Voxels::masses.
Lattice make_from_voxels(const Voxels& voxels, const Material& material, Shear shear = Shear::one);

// The tetrahedra that fill the filled cells, corners as mass indices: five
// to a cell, the central one alternating in a checkerboard, so that
// neighbouring cells split their shared face along the same diagonal as
// make_from_voxels's Shear::one springs.
std::vector<std::array<int, 4>> voxel_tetrahedra(const Voxels& voxels);

// make_from_voxels(voxelise(mesh, spacing), ...).
Lattice make_from_mesh(TriangleMesh mesh, double spacing, const Material& material, Shear shear = Shear::one);

}  // namespace hcosim::models::massspring
