// Quartets: four masses tied by one measure of their positions, a bending
// hinge's dihedral angle (discrete shells, Grinspun, Hirani, Desbrun and
// Schroeder 2003) or a tetrahedron's signed volume; their measures,
// gradients, energies and forces, and the builders that add them.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "models/massspring/lattice.h"

namespace hcosim::models::massspring {

// The signed angle (rad, in (-pi, pi]) from triangle (i, j, k)'s normal to
// triangle (j, i, l)'s about the edge from i to j, at positions x: 0 where
// the two lie flat. g gets its gradient for corners i, j, k, l (rad/m).
// Where either triangle has no area (below 1e-24 m^2, twice) it has no
// normal: the angle is the hinge's rest and the gradient zero.
double dihedral(const Quartet& hinge, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]);

// The signed volume (m^3) of the tetrahedron (i, j, k, l) at positions x,
// (x_j - x_i) . ((x_k - x_i) x (x_l - x_i)) / 6; g gets its gradient for
// the four corners (m^2), which sums to zero.
double volume(const Quartet& tet, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]);

// The quartet's own measure (dihedral or volume) and its gradient.
double measure(const Quartet& q, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]);

// What the quartet's energy and force act on: measure - rest and its
// gradient, except for a volume above its rest (a floor): 0 and a zero
// gradient.
double strain(const Quartet& q, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]);

// Adds a hinge on every edge that two of `triangles` share (indices into
// the lattice's masses, consistently oriented: the second triangle runs the
// edge the other way), at rest in l.rest. A shell of flexural rigidity
// `rigidity` (J) has bending energy D (theta - rest)^2 3 |e|^2 / (A1 + A2)
// per edge e between triangles of areas A1 and A2 (discrete shells), so
// stiffness = 6 D |e|^2 / (A1 + A2); b is `damping` (J s) times the same
// factor. Throws std::invalid_argument for a triangle out of range, an edge
// in more than two triangles or run the same way by both, a negative or
// non-finite rigidity or damping, or a rest triangle of no area.
void add_hinges(Lattice& lattice, const std::vector<Eigen::Vector3i>& triangles, double rigidity, double damping);

// Adds a volume floor for each of `tets` (corner indices; either
// orientation: one of negative volume in l.rest is turned): below `floor`
// (in (0, 1]) times its volume V0 in l.rest, energy
// modulus (V - floor V0)^2 / (2 V0), that of a material of bulk modulus
// `modulus` (Pa) compressed uniformly past the floor; none above it. So
// stiffness = modulus / V0, rest = floor V0 and b = damping (Pa s) / V0.
// Throws std::invalid_argument for a corner out of range, a negative or
// non-finite modulus or damping, a floor outside (0, 1], or a tetrahedron
// of no volume in l.rest (below 1e-18 of its longest edge cubed).
void add_volumes(Lattice& lattice, const std::vector<std::array<int, 4>>& tets, double modulus, double damping,
                 double floor);

// The tetrahedra that fill make_box(nx, ny, nz, ...)'s cells
// (voxel_tetrahedra of its cells, models/massspring/mesh_lattice.h).
std::vector<std::array<int, 4>> box_tetrahedra(int nx, int ny, int nz);

// Energy stiffness s^2 / 2 of a quartet at x (J), s its strain.
double quartet_energy(const Quartet& q, const Eigen::Matrix3Xd& x);

// The force of a quartet on each corner c at (x, v):
// -(stiffness s + b s') g[c] for its strain s and gradient g. Returns s.
double quartet_forces(const Quartet& q, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, Eigen::Vector3d f[4]);

}  // namespace hcosim::models::massspring
