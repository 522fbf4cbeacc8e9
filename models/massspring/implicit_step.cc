#include "models/massspring/simulator_impl.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace hcosim::models::massspring {

const Eigen::SparseMatrix<double>& Simulator::Impl::step_matrix(const Eigen::Matrix3Xd& x, double h) {
  implicit_triplets(lat, springs, quartets, masses, slot, x, h, triplets);
  if (masses != step_masses || springs != step_springs || quartets != step_quartets) {
    const int n = 3 * int(masses.size());
    step_a.resize(n, n);
    step_a.setFromTriplets(triplets.begin(), triplets.end());
    step_value.resize(triplets.size());
    const int* outer = step_a.outerIndexPtr();
    const int* inner = step_a.innerIndexPtr();
    for (std::size_t k = 0; k < triplets.size(); ++k) {
      const int c = int(triplets[k].col());
      step_value[k] = int(std::lower_bound(inner + outer[c], inner + outer[c + 1], int(triplets[k].row())) - inner);
    }
    step_masses = masses, step_springs = springs, step_quartets = quartets;
    return step_a;
  }
  double* value = step_a.valuePtr();
  std::fill(value, value + step_a.nonZeros(), 0.0);
  for (std::size_t k = 0; k < triplets.size(); ++k) value[step_value[k]] += triplets[k].value();
  return step_a;
}

int Simulator::Impl::implicit_euler(State& s, double h) {
  const int m = int(masses.size());
  for (const int i : masses) f.col(i).setZero();
  add_forces(lat, springs, quartets, masses, loads, s.x, s.v, f);
  add_stiffness_times(lat, springs, quartets, s.x, s.v, -h, f);
  Eigen::VectorXd b(3 * m);
  for (int k = 0; k < m; ++k) b.segment<3>(3 * k) = h * f.col(masses[k]);
  const Eigen::SparseMatrix<double>& A = step_matrix(s.x, h);
  cg.setTolerance(opt.tolerance);
  cg.setMaxIterations(std::max(100, 3 * m));
  cg.compute(A);
  if (dv.size() != 3 * m) dv.setZero(3 * m);
  dv = cg.solveWithGuess(b, dv);
  int iterations = int(cg.iterations());
  // CG stalls on very stiff springs (condition ~ (w h)^2); fall back to a
  // direct factorization rather than accept an inexact step.
  if (cg.info() != Eigen::Success) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    if (ldlt.info() != Eigen::Success) throw std::runtime_error("implicit_euler: the step matrix is singular");
    dv = ldlt.solve(b);
  }
  for (int k = 0; k < m; ++k) {
    const int i = masses[k];
    s.v.col(i) += dv.segment<3>(3 * k);
    s.x.col(i) += h * s.v.col(i);
  }
  return iterations;
}

void Simulator::Impl::factor(double h) {
  const int m = int(masses.size());
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(m + 4 * springs.size());
  for (int k = 0; k < m; ++k) t.emplace_back(k, k, lat.mass[masses[k]] + h * lat.drag);
  for (const int si : springs) {
    const Spring& sp = lat.springs[si];
    const double w = h * sp.b + h * h * sp.k;
    const int p = slot[sp.i], q = slot[sp.j];
    if (p >= 0) t.emplace_back(p, p, w);
    if (q >= 0) t.emplace_back(q, q, w);
    if (p >= 0 && q >= 0) t.emplace_back(p, q, -w), t.emplace_back(q, p, -w);
  }
  Eigen::SparseMatrix<double> Q(m, m);
  Q.setFromTriplets(t.begin(), t.end());
  llt.compute(Q);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("local_global: the system matrix is not positive definite");
  factored = masses;
}

void Simulator::Impl::local_global(State& s, double h) {
  if (factored != masses) factor(h);
  const int m = int(masses.size());
  base.resize(m, 3);
  delta.resize(m, 3);
  for (const int i : masses) x0.col(i) = s.x.col(i), f.col(i).setZero();
  quartet_forces(s.x, s.v, false);
  // Ends outside the set do not move: their x is their start.
  auto start = [&](int i) { return slot[i] >= 0 ? x0.col(i) : s.x.col(i); };
  for (int k = 0; k < m; ++k) {
    const int i = masses[k];
    Eigen::Vector3d ext = lat.mass[i] * lat.gravity + f.col(i);
    for (const PointForce& p : loads)
      if (p.mass == i) ext += p.force;
    base.row(k) = lat.mass[i] * h * s.v.col(i).transpose() + h * h * ext.transpose();
    delta.row(k) = h * s.v.col(i).transpose() + h * h * ext.transpose() / lat.mass[i];
  }
  for (int it = 0; it < opt.iterations; ++it) {
    // Local: each spring's closest rest-length vector at the iterate.
    for (int k = 0; k < m; ++k) s.x.col(masses[k]) = x0.col(masses[k]) + delta.row(k).transpose();
    rhs = base;
    for (const int si : springs) {
      const Spring& sp = lat.springs[si];
      double len;
      const Eigen::Vector3d d = -sp.rest * spring_direction(lat, sp, s.x, &len);
      const Eigen::RowVector3d e = h * h * sp.k * (start(sp.i) - start(sp.j) - d).transpose();
      if (slot[sp.i] >= 0) rhs.row(slot[sp.i]) -= e;
      if (slot[sp.j] >= 0) rhs.row(slot[sp.j]) += e;
    }
    // Global: one prefactored solve for the three coordinates.
    delta = llt.solve(rhs);
  }
  for (int k = 0; k < m; ++k) {
    const int i = masses[k];
    s.x.col(i) = x0.col(i) + delta.row(k).transpose();
    s.v.col(i) = delta.row(k).transpose() / h;
  }
}

}  // namespace hcosim::models::massspring
