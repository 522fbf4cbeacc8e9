// Bending of surfaces: the signed dihedral angle of a hinge and its
// gradient, and the hinges of a triangle mesh (discrete shells, Grinspun,
// Hirani, Desbrun and Schroeder 2003).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "models/massspring/lattice.h"

namespace hcosim::models::massspring {

// The signed angle (rad, in (-pi, pi]) from triangle (i, j, k)'s normal to
// triangle (j, i, l)'s about the edge from i to j, at positions x: 0 where
// the two lie flat. g gets its gradient for corners i, j, k, l (rad/m).
// Where either triangle has no area (below 1e-24 m^2, twice) it has no
// normal: the angle is the hinge's rest and the gradient zero.
double dihedral(const Hinge& hinge, const Eigen::Matrix3Xd& x, Eigen::Vector3d g[4]);

// Adds a hinge on every edge that two of `triangles` share (indices into
// the lattice's masses, consistently oriented: the second triangle runs the
// edge the other way), at rest in l.rest. A shell of flexural rigidity
// `rigidity` (J) has bending energy D (theta - rest)^2 3 |e|^2 / (A1 + A2)
// per edge e between triangles of areas A1 and A2 (discrete shells), so
// k_bend = 6 D |e|^2 / (A1 + A2); b is `damping` (J s) times the same
// factor. Throws std::invalid_argument for a triangle out of range, an edge
// in more than two triangles or run the same way by both, a negative or
// non-finite rigidity or damping, or a rest triangle of no area.
void add_hinges(Lattice& lattice, const std::vector<Eigen::Vector3i>& triangles, double rigidity, double damping);

// Energy k_bend (theta - rest)^2 / 2 of a hinge at x (J).
double bending_energy(const Hinge& hinge, const Eigen::Matrix3Xd& x);

// The force of a hinge on each corner c at (x, v): -(k_bend (theta - rest)
// + b theta') g[c]. Returns theta - rest (rad).
double hinge_forces(const Hinge& hinge, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, Eigen::Vector3d f[4]);

}  // namespace hcosim::models::massspring
