// Lattices for organ-like objects (001 Fig 9): a closed triangle mesh,
// read from OBJ, voxelised into a box lattice that fills its inside.
#pragma once

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

// Box lattice (make_box's springs) on the cells of a grid of `spacing` whose
// centres lie inside `mesh`; masses at the cells' corners. Welds and checks
// the mesh first. Throws std::invalid_argument if no cell is inside.
Lattice make_from_mesh(TriangleMesh mesh, double spacing, const Material& material, Shear shear = Shear::one);

}  // namespace hcosim::models::massspring
