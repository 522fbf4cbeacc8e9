// Surfaces of the hybrid model: the behavior lattice's boundary as the
// mapping cage, the dense visual mesh (001 Fig 7: 5402 vertices and 10800
// triangles at 30 subdivisions), and per-vertex normals for display.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "models/massspring/mesh_lattice.h"

namespace hcosim::models::deformable {

// The boundary of an nx x ny x nz grid of nodes (node i + nx (j + ny k)) as a closed
// triangle mesh: its nodes and triangles indexing into `nodes`,
// counter-clockwise seen from outside. (nx ny nz - (nx-2)(ny-2)(nz-2))
// nodes, two triangles per boundary square. Throws std::invalid_argument
// for fewer than 2 nodes per side.
struct GridSurface {
  std::vector<int> nodes;
  std::vector<Eigen::Vector3i> triangles;
};
GridSurface grid_surface(int nx, int ny, int nz);

// The boundary of the filled cells of `voxels` as a closed triangle mesh:
// two triangles per square between a filled cell and one that is not (or
// the grid's outside), counter-clockwise seen from outside; `nodes` are
// mass indices (Voxels::masses). grid_surface is that of a full box.
GridSurface voxel_surface(const models::massspring::Voxels& voxels);

// A box from `lo` to `hi` (m) with rounded edges and corners: the
// superellipsoid |x|^p + |y|^p + |z|^p = 1 in the box's normalised frame,
// p = `exponent` (2: ellipsoid; large: the box itself), meshed as a cube
// of `subdivisions` squares per edge projected onto it: 6 s^2 + 2 vertices,
// 12 s^2 triangles. Its face centres touch the box. Throws
// std::invalid_argument for subdivisions < 1, exponent < 2 or an empty box.
models::massspring::TriangleMesh rounded_box(int subdivisions, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                             double exponent);

// The height (m) of the mesh at positions x over the point `at` (x, y): the
// highest z where the vertical line through it crosses a triangle;
// -infinity where none does.
double height_over(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles, const Eigen::Vector2d& at);

// m: how deep q is inside the closed mesh at positions x: its distance
// from the mesh's nearest point, negative outside. How far the stylus's
// tip is drawn inside an object.
double depth_inside(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles, const Eigen::Vector3d& q);

// Unit area-weighted vertex normals of a triangle mesh at positions x; a
// vertex whose triangles all collapsed gets +z rather than NaN.
Eigen::Matrix3Xd vertex_normals(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& triangles);

}  // namespace hcosim::models::deformable
