// Mass-spring lattices: masses, springs and anchors of the seeds' shapes
// (000 Fig 7: plane sheet, semi-sphere; 001 Fig 1 and 7: box of masses with
// structural and shear springs). SI units throughout, world frame.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hcosim::models::massspring {

// A spring-damper between masses i and j (000 eq 13, 001 eq 2): force
// k (|l| - rest) along l, plus b times the rate of change of |l|.
struct Spring {
  int i = 0, j = 0;
  double rest = 0;  // m, >= 0
  double k = 0;     // N/m, >= 0
  double b = 0;     // N s/m, >= 0
};

// What a quartet measures of its four masses.
enum class Measure : std::uint8_t {
  // rad, in (-pi, pi]: the signed dihedral angle about the edge (i, j)
  // from triangle (i, j, k)'s normal to triangle (j, i, l)'s; a bending
  // hinge (discrete shells, Grinspun et al. 2003). The sign tells a fold
  // one way from the other, so a dome pressed inside out is pushed back;
  // springs across the edge could not tell them apart.
  angle,
  // m^3: the signed volume of the tetrahedron (i, j, k, l), positive when
  // l lies on the side that (i, j, k) faces counter-clockwise; a floor,
  // acting only below its rest. A collapsed or inverted element is pushed
  // back through zero, which no spring can do (a mirrored element has its
  // springs' rest lengths), and a press cannot push a mass through the
  // layer below it; above the floor the springs act alone.
  volume,
};

// Four masses tied by one measure m of their positions
// (models/massspring/quartet.h): energy stiffness (m - rest)^2 / 2 and a
// damper b on m's rate, so the force on corner c is
// -(stiffness (m - rest) + b m') dm/dx_c (for a volume, below rest only).
struct Quartet {
  int i = 0, j = 0, k = 0, l = 0;
  double rest = 0;       // rad (angle, in (-pi, pi)) or m^3 (volume, > 0)
  double stiffness = 0;  // >= 0: N m/rad (angle) or N/m^5 (volume)
  double b = 0;          // >= 0: N m s/rad (angle) or N s/m^5 (volume)
  Measure measure = Measure::angle;
};

// The behavior model's elements. Per-element mass, stiffness and damping may
// differ (001 Fig 8); builders make them homogeneous.
struct Lattice {
  Eigen::Matrix3Xd rest;  // m, rest position of each mass
  Eigen::VectorXd mass;   // kg, > 0
  std::vector<Spring> springs;
  std::vector<Quartet> quartets;                      // bending hinges and volume elements
  std::vector<std::uint8_t> anchored;                 // 1: held at its rest position
  double drag = 0;                                    // N s/m per mass: air friction D v_i (000 eq 13)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // m/s^2

  int size() const { return int(mass.size()); }
};

// Homogeneous material of a builder's output.
struct Material {
  double mass = 1e-3;  // kg per mass
  double k = 50;       // N/m per spring
  double b = 0;        // N s/m per spring
  double drag = 0;     // N s/m per mass
};

// Throws std::invalid_argument naming the first bad element: sizes that
// disagree, non-finite values, mass <= 0, negative k/b/rest, a spring whose
// ends are equal or out of range, a quartet whose corners repeat or are
// out of range, a hinge whose rest angle is outside (-pi, pi) or a volume
// whose rest is not > 0.
void check(const Lattice& lattice);

// nx x ny masses in the z = 0 plane, `spacing` apart, corner at the origin;
// structural springs along rows and columns, both diagonals of each cell as
// shear springs. The border is anchored, as a sheet held in a frame.
Lattice make_sheet(int nx, int ny, double spacing, const Material& material);

// Hemispherical shell of `radius` over the z = 0 plane, centred at the
// origin: `rings` latitude rings (the base ring included) of `segments`
// masses each plus the pole; springs along the triangulated surface. The
// base ring is anchored.
Lattice make_semisphere(int rings, int segments, double radius, const Material& material);

// A surface of springs: a mass at each of `vertices` (m, its rest
// position) and a spring along every edge of `triangles` (indices into
// them), nothing anchored. Throws std::invalid_argument for a corner out of
// range or a triangle that repeats one.
Lattice make_shell(const Eigen::Matrix3Xd& vertices, const std::vector<Eigen::Vector3i>& triangles,
                   const Material& material);

// Diagonal layout of shear springs in the box: `one` triangulates each
// lattice face with a single diagonal, alternating in a checkerboard (a
// rigid lattice, 5130 springs at 10^3 masses, nearest to 001 Fig 7's 5400);
// `both` puts both diagonals on each face (isotropic, 7560 springs).
enum class Shear { one, both };

// nx x ny x nz masses, `spacing` apart, corner at the origin, with
// structural springs along the axes and face-diagonal shear springs
// (001 Fig 1). Nothing is anchored.
Lattice make_box(int nx, int ny, int nz, double spacing, const Material& material, Shear shear = Shear::one);

// Anchors every mass whose rest position satisfies `pred`; returns how many.
template <class Pred>
int anchor_where(Lattice& lattice, Pred&& pred) {
  int n = 0;
  for (int i = 0; i < lattice.size(); ++i)
    if (pred(Eigen::Vector3d(lattice.rest.col(i)))) lattice.anchored[i] = 1, ++n;
  return n;
}

}  // namespace hcosim::models::massspring
