#include "models/deformable/compliance.h"

#include <algorithm>

#include <Eigen/SparseCholesky>

#include "models/deformable/hybrid_build.h"

namespace hcosim::models::deformable {

namespace {

// N/m: the behavior model's stiffness at rest over its free masses (mass
// i's x, y, z at 3 dof[i] + 0, 1, 2; dof -1: anchored). The springs' is
// their axial stiffness (at rest they carry no tension, and no volume
// floor is engaged); the FEM's and the modal model's is the FEM's.
Eigen::SparseMatrix<double> rest_stiffness(const HybridSpec& spec, const models::massspring::Lattice& lat,
                                           const std::vector<int>& dof, int free) {
  std::vector<Eigen::Triplet<double>> t;
  auto add = [&](int i, int j, int r, int c, double v) {
    if (dof[i] >= 0 && dof[j] >= 0) t.emplace_back(3 * dof[i] + r, 3 * dof[j] + c, v);
  };
  if (spec.behavior_model != BehaviorModel::springs) {
    const Eigen::SparseMatrix<double> k =
        models::fem::Corotational(hybrid_mesh(spec), spec.fem, models::fem::Options{}).rest_stiffness();
    for (int c = 0; c < k.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it)
        add(int(it.row() / 3), int(it.col() / 3), int(it.row() % 3), int(it.col() % 3), it.value());
  } else {
    for (const models::massspring::Spring& sp : lat.springs) {
      const Eigen::Vector3d d = lat.rest.col(sp.j) - lat.rest.col(sp.i);
      if (d.norm() <= 0) continue;
      const Eigen::Matrix3d b = sp.k * d.normalized() * d.normalized().transpose();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          add(sp.i, sp.i, r, c, b(r, c)), add(sp.j, sp.j, r, c, b(r, c)), add(sp.i, sp.j, r, c, -b(r, c)),
              add(sp.j, sp.i, r, c, -b(r, c));
    }
  }
  Eigen::SparseMatrix<double> k(3 * free, 3 * free);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

// m/N, by row of `rows` (points x cage): how far each point of the drawn
// surface sinks along -normals.col(row) under 1 N pressing it, spread
// over the cage's masses by its row as touch() spreads the force, at
// rest. With K = P' L D L' P, a push p's compliance p' K^-1 p is
// |D^-1/2 L^-1 P p|^2: one factorisation, then a forward substitution a
// point that visits only the columns its few nonzeros reach.
std::vector<double> rest_compliance(const HybridSpec& spec, const models::massspring::Lattice& lat, const Weights& rows,
                                    const std::vector<int>& cage, const Eigen::Matrix3Xd& normals) {
  std::vector<int> dof(lat.size(), -1);
  int free = 0;
  for (int i = 0; i < lat.size(); ++i)
    if (!lat.anchored[i]) dof[i] = free++;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(rest_stiffness(spec, lat, dof, free));
  check_hybrid(ldlt.info() == Eigen::Success,
               "the behavior model's stiffness at rest is singular: a mass holds by nothing");
  const Eigen::SparseMatrix<double>& l = ldlt.matrixL().nestedExpression();
  const Eigen::VectorXi& to = ldlt.permutationP().indices();
  const Eigen::VectorXd& d = ldlt.vectorD();
  std::vector<double> c(rows.rows(), 0);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * free);
  for (int v = 0; v < rows.rows(); ++v) {
    int first = 3 * free;
    for (Weights::InnerIterator w(rows, v); w; ++w)
      if (const int m = dof[cage[w.col()]]; m >= 0)
        for (int k = 0; k < 3; ++k) {
          y[to[3 * m + k]] += w.value() * normals(k, v);
          first = std::min(first, int(to[3 * m + k]));
        }
    for (int j = first; j < 3 * free; ++j) {
      if (y[j] == 0) continue;
      for (Eigen::SparseMatrix<double>::InnerIterator e(l, j); e; ++e)
        if (e.row() > j) y[e.row()] -= e.value() * y[j];
      c[v] += y[j] * y[j] / d[j];
      y[j] = 0;
    }
  }
  return c;
}

// The same in the modal model's kept modes: its static answer to a load
// is the sum over them of the load's modal force times the shape over the
// frequency squared.
std::vector<double> modal_compliance(const models::fem::Modal& modal, const Weights& rows, const std::vector<int>& cage,
                                     const Eigen::Matrix3Xd& normals) {
  std::vector<Eigen::Matrix3Xd> shapes;
  for (int k = 0; k < modal.modes(); ++k) shapes.push_back(modal.shape(k));
  std::vector<double> c(rows.rows(), 0);
  for (int v = 0; v < rows.rows(); ++v)
    for (int k = 0; k < modal.modes(); ++k) {
      double q = 0;  // the modal force of 1 N along -n, spread by the row
      for (Weights::InnerIterator w(rows, v); w; ++w) q += w.value() * normals.col(v).dot(shapes[k].col(cage[w.col()]));
      c[v] += q * q / (modal.frequencies()[k] * modal.frequencies()[k]);
    }
  return c;
}

}  // namespace

std::vector<double> surface_compliance(const HybridSpec& spec, const models::massspring::Lattice& lat,
                                       const models::fem::Modal* modal, const Weights& rows,
                                       const std::vector<int>& cage, const Eigen::Matrix3Xd& normals) {
  return modal ? modal_compliance(*modal, rows, cage, normals) : rest_compliance(spec, lat, rows, cage, normals);
}

std::unique_ptr<models::fem::Modal> modal_of(const HybridSpec& spec) {
  if (spec.behavior_model != BehaviorModel::modal) return nullptr;
  const models::fem::Corotational fem(hybrid_mesh(spec), spec.fem, models::fem::Options{});
  return std::make_unique<models::fem::Modal>(fem, models::fem::ModalOptions{spec.behavior.dt, spec.modes});
}

}  // namespace hcosim::models::deformable
