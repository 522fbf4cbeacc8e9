// Linear modal reduction of the FEM (Pentland and Williams 1989; James and
// Pai's DyRT, 2002): the mesh linearised at rest, K phi = w^2 M phi over its
// free nodes, and its lowest modes kept, each a damped oscillator
// q'' + (alpha + beta w^2) q' + w^2 q = phi^T f integrated exactly over a
// step with the step's loads held (zero-order hold). Any step is stable,
// a load that changes only at step boundaries is followed with no time
// error, and a step costs about 4 x modes x 3 x nodes multiply-adds
// whatever the material's stiffness. Small strains only: a mode is linear,
// so a large rotation stretches the body and an inverted element is not
// pushed back (Corotational does both).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "models/fem/corotational.h"

namespace hcosim::models::fem {

struct ModalOptions {
  double dt = 1e-3;  // s, > 0
  int modes = 32;    // the lowest ones kept, 1 to 3 x the free nodes
};

class Modal {
 public:
  // The most free degrees of freedom (3 per free node) the dense
  // eigensolve takes: its time grows with their cube (seconds at 3000).
  static constexpr int kMaxDofs = 4500;

  // The modes of `fem`'s mesh, material (Rayleigh damping included) and
  // anchors. Throws std::invalid_argument naming the problem: dt not
  // finite and > 0, modes out of range, or more free dofs than kMaxDofs.
  Modal(const Corotational& fem, const ModalOptions& options);

  // Advances `state` by options().dt under point loads (N) held over the
  // step; loads on anchored nodes go to the anchor. Of the state's
  // displacement from rest and its velocity, only their part in the kept
  // modes is carried (all of it, for a state this model stepped).
  // Anchored nodes stay at rest. Throws std::invalid_argument as
  // Corotational::step does.
  void step(models::massspring::State& state, const std::vector<models::massspring::PointForce>& loads) const;

  // rad/s, ascending: the kept modes' undamped frequencies.
  const Eigen::VectorXd& frequencies() const { return omega_; }
  // The kept modes as displacements of every node (anchored ones zero),
  // mass-normalised (phi^T M phi = 1), 3 x nodes each.
  Eigen::Matrix3Xd shape(int mode) const;
  int modes() const { return int(omega_.size()); }
  // m/N: the static displacement of free `node` per unit force held on it,
  // in the kept modes (the sum of phi phi^T / w^2 over them): this model's
  // answer to a press held at one node. Fewer modes make it stiffer.
  // Throws std::invalid_argument for a node out of range or anchored, or
  // when a kept mode has no stiffness (a free body's rigid modes).
  Eigen::Matrix3d compliance(int node) const;
  const ModalOptions& options() const { return options_; }

 private:
  ModalOptions options_;
  Eigen::Matrix3Xd rest_;
  std::vector<int> free_;    // the free nodes, in order; their dofs 3k, 3k+1, 3k+2
  std::vector<int> dof_;     // per node, its first free dof, or -1 if anchored
  Eigen::MatrixXd phi_;      // free dofs x modes: the mass-normalised shapes
  Eigen::MatrixXd project_;  // modes x free dofs: phi^T M, from displacement to modal coordinates
  Eigen::VectorXd omega_;
  int rigid_ = 0;  // kept modes with no stiffness
  // Per mode, one step's exact map of (q, q') and the response to a unit
  // modal force held over it.
  std::vector<Eigen::Matrix2d> advance_;
  std::vector<Eigen::Vector2d> forced_;
};

}  // namespace hcosim::models::fem
