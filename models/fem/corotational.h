// Corotational linear tetrahedral finite elements (Mueller and Gross 2004;
// SOFA's TetrahedronFEMForceField with method "polar"): each tetrahedron's
// linear elastic stiffness acts in its own rotated frame, the rotation
// taken from the polar decomposition of its deformation gradient, so that
// rigid rotations cost no energy and an inverted element is pushed back
// (the rotation keeps det R = +1). Stepped by linearised implicit Euler
// or the trapezoidal rule (rotations fixed over a step), solved by
// conjugate gradient on Eigen's sparse matrices. The behavior models' reference:
// a material of Young's modulus, Poisson's ratio and density rather than
// springs tuned by hand.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "models/massspring/forces.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::fem {

struct Material {
  double young = 5000;    // Pa, > 0
  double poisson = 0.3;   // in (-1, 0.5)
  double density = 1000;  // kg/m^3, > 0
  double alpha = 0;       // 1/s, >= 0: Rayleigh damping on the mass
  double beta = 0;        // s, >= 0: Rayleigh damping on the stiffness
};

// Time stepping, both linearised with the rotations of the step's start:
// implicit_euler damps every mode by 1 / sqrt(1 + (w dt)^2) per step
// (stable, first order); trapezoidal (Newmark's average acceleration)
// keeps an undamped linear mode's energy (stable, second order): the
// reference runs use it.
enum class Scheme { implicit_euler, trapezoidal };

struct Options {
  double dt = 1e-3;         // s, > 0
  double tolerance = 1e-8;  // CG relative residual, in (0, 1)
  Scheme scheme = Scheme::implicit_euler;
};

// A tetrahedral mesh: rest positions (m), tetrahedra (corner indices,
// either orientation) and which nodes are anchored at rest.
struct Mesh {
  Eigen::Matrix3Xd rest;
  std::vector<std::array<int, 4>> tets;
  std::vector<std::uint8_t> anchored;
  std::vector<double> scale;  // per tetrahedron, > 0: times Young's modulus (empty: all 1)
  int size() const { return int(rest.cols()); }
};

// A box of nx x ny x nz nodes `spacing` apart, corner at the origin, five
// tetrahedra to a cell (models::massspring::box_tetrahedra), nothing anchored.
Mesh box_mesh(int nx, int ny, int nz, double spacing);

struct StepInfo {
  int iterations = 0;   // CG
  bool direct = false;  // CG did not converge: solved by a sparse LDL^T instead
};

class Corotational {
 public:
  // Throws std::invalid_argument naming the problem: a material or option
  // out of range, sizes that disagree, a corner out of range or repeated,
  // a tetrahedron of no volume at rest, or a node in no tetrahedron that
  // is not anchored.
  Corotational(Mesh mesh, const Material& material, const Options& options);
  ~Corotational();
  Corotational(const Corotational&) = delete;
  Corotational& operator=(const Corotational&) = delete;

  // Advances `state` (positions and velocities of every node; quiet is
  // unused) by options().dt under point loads (N). Anchored nodes stay at
  // rest; held ones where the state puts them, moving at its velocity.
  // Throws std::invalid_argument for a state of the wrong size or a bad
  // load, std::runtime_error if the step's velocities are not finite
  // (the state is then left as before the step).
  StepInfo step(models::massspring::State& state, const std::vector<models::massspring::PointForce>& loads);

  // Holds or releases a node that is not anchored: kinematic while held.
  void hold(int node, bool held);

  // N: the elastic force of the elements on `node` in `state` (what holds
  // a held node at rest feels, reversed).
  Eigen::Vector3d force_on(int node, const models::massspring::State& state) const;

  // J: the corotated elastic energy at x.
  double energy(const Eigen::Matrix3Xd& x) const;

  // N/m: the linear stiffness at rest, 3 x size() square (node i's x, y, z
  // at 3i, 3i+1, 3i+2), anchored nodes included: the Hessian of energy()
  // at the rest shape, which Modal reduces.
  Eigen::SparseMatrix<double> rest_stiffness() const;

  const Mesh& mesh() const;
  const Eigen::VectorXd& mass() const;  // kg per node, lumped
  const Material& material() const;
  const Options& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Throws std::invalid_argument naming the problem unless `state` has
// `nodes` nodes, all finite, and every load is finite and on one of them.
void check_step(int nodes, const models::massspring::State& state,
                const std::vector<models::massspring::PointForce>& loads);

// At rest: positions the mesh's rest, velocities zero.
models::massspring::State rest_state(const Mesh& mesh);

}  // namespace hcosim::models::fem
