// Forces, energy and their derivatives for a lattice (000 eq 8-13, 001 eq 2).
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "models/massspring/lattice.h"

namespace hcosim::models::massspring {

// External point force on one mass, e.g. the haptic stylus at the contacted
// vertex (000 §2.2); it reaches the rest of the object through the springs.
struct PointForce {
  int mass = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N, world frame
};

// Unit vector from mass i to mass j of `s`. Below 1e-12 m the current
// direction is undefined; the rest direction is used so that a collapsed
// lattice expands the way it was built (zero for zero-length springs).
Eigen::Vector3d spring_direction(const Lattice& lattice, const Spring& s, const Eigen::Matrix3Xd& x, double* length);

// The same as spring_direction into u[3], returning the length; inline for
// the force loops, which call it once per spring per evaluation.
inline double spring_axis(const Lattice& lattice, const Spring& s, const Eigen::Matrix3Xd& x, double u[3]) {
  const double* X = x.data();
  const int a = 3 * s.i, b = 3 * s.j;
  u[0] = X[b] - X[a], u[1] = X[b + 1] - X[a + 1], u[2] = X[b + 2] - X[a + 2];
  double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  if (len > 1e-12) {
    const double inv = 1 / len;
    u[0] *= inv, u[1] *= inv, u[2] *= inv;
  } else {
    const Eigen::Vector3d d = spring_direction(lattice, s, x, &len);
    u[0] = d.x(), u[1] = d.y(), u[2] = d.z();
  }
  return len;
}

// Tension of spring s (N, positive when it pulls its ends together):
// k (|l| - rest) plus b times the rate of change of |l|; u gets its axis,
// from mass i to mass j.
inline double spring_tension(const Lattice& lattice, const Spring& s, const Eigen::Matrix3Xd& x,
                             const Eigen::Matrix3Xd& v, double u[3]) {
  const double len = spring_axis(lattice, s, x, u);
  const double* V = v.data();
  const int a = 3 * s.i, b = 3 * s.j;
  const double rate = u[0] * (V[b] - V[a]) + u[1] * (V[b + 1] - V[a + 1]) + u[2] * (V[b + 2] - V[a + 2]);
  return s.k * (len - s.rest) + s.b * rate;
}

// Adds to f (3 x n, N) the forces of `springs` (indices into
// lattice.springs) on both their ends and of `quartets` (into
// lattice.quartets) on their four corners, and for `masses` the drag, gravity and point
// forces. Forces on anchored masses are computed but unused.
void add_forces(const Lattice& lattice, const std::vector<int>& springs, const std::vector<int>& quartets,
                const std::vector<int>& masses, const std::vector<PointForce>& loads, const Eigen::Matrix3Xd& x,
                const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

struct Energy {
  double kinetic = 0;  // J
  double elastic = 0;  // J, springs
  double bending = 0;  // J, angle quartets (hinges)
  double volume = 0;   // J, volume quartets
  double gravity = 0;  // J, relative to the rest configuration: -m g . (x - rest)
  double total() const { return kinetic + elastic + bending + volume + gravity; }
};
Energy energy(const Lattice& lattice, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v);

// Total linear momentum (kg m/s) of the masses that are not anchored.
Eigen::Vector3d momentum(const Lattice& lattice, const Eigen::Matrix3Xd& v);

// The linearised implicit Euler matrix M + h C + h^2 K over `masses` (3 rows
// each, in that order; `slot[i]` is mass i's position in `masses` or -1 for
// a mass held fixed), with K = -df/dx and C = -df/dv at x. The geometric
// part of K of a compressed spring is dropped so that the matrix stays
// symmetric positive definite; so is a quartet's curvature term, leaving
// stiffness g g^T for its measure's gradient g (Gauss-Newton).
Eigen::SparseMatrix<double> implicit_matrix(const Lattice& lattice, const std::vector<int>& springs,
                                            const std::vector<int>& quartets, const std::vector<int>& masses,
                                            const std::vector<int>& slot, const Eigen::Matrix3Xd& x, double h);
// The same as (row, column, value) triplets, duplicates to be summed, in
// `out` (cleared first). The same springs, quartets and masses give the
// same rows and columns in the same order whatever x and h, so a caller
// may keep the matrix and refill its values in place.
void implicit_triplets(const Lattice& lattice, const std::vector<int>& springs, const std::vector<int>& quartets,
                       const std::vector<int>& masses, const std::vector<int>& slot, const Eigen::Matrix3Xd& x,
                       double h, std::vector<Eigen::Triplet<double>>& out);

// K v for the same K (3 x n result), used on the right-hand side.
void add_stiffness_times(const Lattice& lattice, const std::vector<int>& springs, const std::vector<int>& quartets,
                         const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double scale, Eigen::Matrix3Xd& out);

}  // namespace hcosim::models::massspring
