// Maps from a coarse model to a dense visual mesh (001 §II.B, "mapping
// functions"): mean value coordinates for closed triangle meshes (Ju,
// Schaefer and Warren 2005), a truncated sparse variant, and trilinear
// embedding in a voxel grid as the cheap comparison. Each is a sparse
// matrix W, precomputed once: deformed points = cage positions * W^T.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace hcosim::models::deformable {

using Weights = Eigen::SparseMatrix<double, Eigen::RowMajor>;  // points x cage vertices

// Mean value coordinates of each point (3 x m) with respect to the closed
// triangle mesh (cage_vertices 3 x n, triangles counter-clockwise seen from
// outside). Rows sum to 1 and reproduce linear functions exactly, inside
// and outside the cage; a point on a cage vertex, edge or face gets the
// vertex or that face's barycentric weights (no NaN). Throws
// std::invalid_argument for a bad triangle index or a non-finite point.
Weights mean_value_weights(const Eigen::Matrix3Xd& cage_vertices, const std::vector<Eigen::Vector3i>& triangles,
                           const Eigen::Matrix3Xd& points);

// Each row keeping only its largest weights, whose absolute values add up
// to at least `keep` (in (0, 1]) of the row's, renormalised to sum 1.
Weights truncate(const Weights& w, double keep);

// Trilinear weights of each point in the grid of nx x ny x nz nodes
// `spacing` apart from `origin` (node i + nx (j + ny k)); points outside
// take the nearest cell's extrapolation.
Weights trilinear_weights(int nx, int ny, int nz, double spacing, const Eigen::Vector3d& origin,
                          const Eigen::Matrix3Xd& points);

// The points of `w` for cage positions x (3 x n).
Eigen::Matrix3Xd apply(const Weights& w, const Eigen::Matrix3Xd& x);

// The same map by columns, for displacements: rest_points + u W^T, reading
// only the columns of cage vertices whose displacement u (3 x n) exceeds
// `tolerance` (m, per coordinate), so that a local dent costs what it
// moves, not the whole mesh. Equal to apply(W, rest + u) wherever W
// reproduces rest_points, to within tolerance times the largest row sum
// of |W| (1 for mean value coordinates inside a convex cage). Weights are
// stored as float, two thirds of the bytes the map reads each frame (a
// million weights at seed scale); float's 1e-7 relative error on a
// centimetre displacement is a nanometre. Sums are kept in double.
using ColumnWeights = Eigen::SparseMatrix<float, Eigen::ColMajor>;
Eigen::Matrix3Xd apply_moved(const ColumnWeights& w, const Eigen::Matrix3Xd& rest_points, const Eigen::Matrix3Xd& u,
                             double tolerance = 0);

}  // namespace hcosim::models::deformable
