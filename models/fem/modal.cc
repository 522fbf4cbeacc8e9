#include "models/fem/modal.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/MatrixFunctions>

namespace hcosim::models::fem {

namespace {

void need_modal(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("fem modal: " + what);
}

}  // namespace

Modal::Modal(const Corotational& fem, const ModalOptions& options) : options_(options), rest_(fem.mesh().rest) {
  need_modal(options.dt > 0 && std::isfinite(options.dt), "dt must be finite and > 0");
  const int n = fem.mesh().size();
  dof_.assign(n, -1);
  for (int i = 0; i < n; ++i)
    if (!fem.mesh().anchored[i]) dof_[i] = 3 * int(free_.size()), free_.push_back(i);
  const int dofs = 3 * int(free_.size());
  need_modal(dofs > 0, "the mesh has no free node");
  need_modal(dofs <= kMaxDofs,
             std::to_string(dofs) + " free dofs, more than the dense eigensolve's " + std::to_string(kMaxDofs));
  need_modal(options.modes >= 1 && options.modes <= dofs,
             "modes must be in 1.." + std::to_string(dofs) + ", not " + std::to_string(options.modes));

  // K phi = w^2 M phi with M lumped (diagonal): the symmetric problem
  // M^-1/2 K M^-1/2 u = w^2 u, phi = M^-1/2 u.
  Eigen::VectorXd root(dofs);
  for (std::size_t k = 0; k < free_.size(); ++k) root.segment<3>(3 * k).setConstant(std::sqrt(fem.mass()[free_[k]]));
  const Eigen::SparseMatrix<double> k = fem.rest_stiffness();
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(dofs, dofs);
  for (int col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it) {
      const int r = dof_[it.row() / 3], c = dof_[it.col() / 3];
      if (r >= 0 && c >= 0) s(r + it.row() % 3, c + it.col() % 3) += it.value();
    }
  s = root.cwiseInverse().asDiagonal() * s * root.cwiseInverse().asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(s);
  need_modal(eig.info() == Eigen::Success, "the eigensolve failed");
  const int m = options.modes;
  const Eigen::MatrixXd u = eig.eigenvectors().leftCols(m);
  phi_ = root.cwiseInverse().asDiagonal() * u;
  project_ = u.transpose() * root.asDiagonal();
  // A free body's rigid modes come out at w^2 of about -1e-12 of the others.
  omega_ = eig.eigenvalues().head(m).cwiseMax(0).cwiseSqrt();
  rigid_ = int((eig.eigenvalues().head(m).array() <= 1e-9 * eig.eigenvalues().maxCoeff()).count());

  // Each mode's exact step: exp(h A) of the oscillator with its force as a
  // constant third state, A = [0 1 0; -w^2 -c 1; 0 0 0], c = alpha + beta w^2.
  const Material& mat = fem.material();
  for (int i = 0; i < m; ++i) {
    const double w2 = omega_[i] * omega_[i];
    Eigen::Matrix3d a;
    a << 0, 1, 0, -w2, -(mat.alpha + mat.beta * w2), 1, 0, 0, 0;
    const Eigen::Matrix3d e = (options.dt * a).exp();
    advance_.push_back(e.topLeftCorner<2, 2>());
    forced_.push_back(e.topRightCorner<2, 1>());
  }
}

void Modal::step(models::massspring::State& s, const std::vector<models::massspring::PointForce>& loads) const {
  check_step(int(rest_.cols()), s, loads);
  const int dofs = int(phi_.rows());
  Eigen::VectorXd u(dofs), w(dofs);
  for (std::size_t k = 0; k < free_.size(); ++k) {
    u.segment<3>(3 * k) = s.x.col(free_[k]) - rest_.col(free_[k]);
    w.segment<3>(3 * k) = s.v.col(free_[k]);
  }
  Eigen::VectorXd q = project_ * u, qd = project_ * w, p = Eigen::VectorXd::Zero(modes());
  for (const models::massspring::PointForce& l : loads)
    if (dof_[l.mass] >= 0) p += phi_.middleRows<3>(dof_[l.mass]).transpose() * l.force;
  for (int i = 0; i < modes(); ++i) {
    const Eigen::Vector2d next = advance_[i] * Eigen::Vector2d(q[i], qd[i]) + forced_[i] * p[i];
    q[i] = next[0], qd[i] = next[1];
  }
  u.noalias() = phi_ * q;
  w.noalias() = phi_ * qd;
  s.x = rest_;
  s.v.setZero();
  for (std::size_t k = 0; k < free_.size(); ++k) {
    s.x.col(free_[k]) += u.segment<3>(3 * k);
    s.v.col(free_[k]) = w.segment<3>(3 * k);
  }
  s.t += options_.dt;
}

Eigen::Matrix3d Modal::compliance(int node) const {
  need_modal(node >= 0 && node < int(dof_.size()) && dof_[node] >= 0, "no free node " + std::to_string(node));
  need_modal(rigid_ == 0, std::to_string(rigid_) + " kept modes have no stiffness: a free body has no static answer");
  const auto rows = phi_.middleRows<3>(dof_[node]);
  return rows * omega_.cwiseAbs2().cwiseInverse().asDiagonal() * rows.transpose();
}

Eigen::Matrix3Xd Modal::shape(int mode) const {
  need_modal(mode >= 0 && mode < modes(), "no mode " + std::to_string(mode));
  Eigen::Matrix3Xd out = Eigen::Matrix3Xd::Zero(3, rest_.cols());
  for (std::size_t k = 0; k < free_.size(); ++k) out.col(free_[k]) = phi_.col(mode).segment<3>(3 * k);
  return out;
}

}  // namespace hcosim::models::fem
