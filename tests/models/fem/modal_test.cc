// The modal reduction against independent references: the corotational
// FEM stepped finely in small motion, a direct sparse solve of the linear
// statics, a free body's rigid acceleration, and the stiffness and mass
// themselves for its modes; exact at steps past any explicit limit; bad
// input named.
#include "models/fem/modal.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/SparseCholesky>

namespace hcosim::models::fem {
namespace {

using models::massspring::PointForce;
using models::massspring::State;

// A 2 x 2 x 3 cm block of 1 cm cells, its floor anchored, of a soft
// solid (12.5 kPa, as bench massspring's cube) damped on the mass.
Mesh block(bool anchored = true) {
  Mesh m = box_mesh(3, 3, 4, 0.01);
  for (int i = 0; i < m.size(); ++i) m.anchored[i] = anchored && m.rest(2, i) < 1e-12;
  return m;
}

Material solid(double alpha) {
  Material mat;
  mat.young = 12.5e3, mat.poisson = 0.25, mat.density = 1000, mat.alpha = alpha;
  return mat;
}

// `total` N along z spread over the top face's nodes.
std::vector<PointForce> top_load(const Mesh& m, double total) {
  std::vector<PointForce> loads;
  const double top = m.rest.row(2).maxCoeff();
  for (int i = 0; i < m.size(); ++i)
    if (m.rest(2, i) > top - 1e-12) loads.push_back({i, Eigen::Vector3d::Zero()});
  for (PointForce& p : loads) p.force.z() = total / double(loads.size());
  return loads;
}

// J: 1/2 u^T K u + 1/2 v^T M v of a state, from the FEM's own matrices.
double linear_energy(const Corotational& f, const State& s) {
  const Eigen::Matrix3Xd u = s.x - f.mesh().rest;
  const Eigen::Map<const Eigen::VectorXd> uv(u.data(), u.size());
  double kinetic = 0;
  for (int i = 0; i < f.mesh().size(); ++i) kinetic += 0.5 * f.mass()[i] * s.v.col(i).squaredNorm();
  return 0.5 * uv.dot(f.rest_stiffness() * uv) + kinetic;
}

int free_dofs(const Mesh& m) {
  int n = 0;
  for (const std::uint8_t a : m.anchored) n += a ? 0 : 3;
  return n;
}

// A press of the top held for 0.1 s, then let go: with every mode kept
// and 10 ms steps, the positions every 10 ms follow the corotational FEM
// stepped by the trapezoidal rule at 20 us (converged in time), the load
// small enough (a 1e-4 strain) that rotations do not matter.
TEST(FemModal, WithEveryModeItFollowsTheFemInSmallMotion) {
  const Mesh m = block();
  const std::vector<PointForce> load = top_load(m, -5e-4), none;
  Options fine;
  fine.dt = 2e-5, fine.scheme = Scheme::trapezoidal, fine.tolerance = 1e-12;
  Corotational f(m, solid(5), fine);
  ModalOptions mo;
  mo.dt = 1e-2, mo.modes = free_dofs(m);
  const Modal modal(f, mo);
  State a = rest_state(m), b = rest_state(m);
  double num = 0, den = 0;
  for (int k = 0; k < 20; ++k) {
    const bool loaded = k < 10;
    for (int j = 0; j < 500; ++j) f.step(a, loaded ? load : none);
    modal.step(b, loaded ? load : none);
    num += (b.x - a.x).squaredNorm();
    den += (a.x - m.rest).squaredNorm();
  }
  const double error = std::sqrt(num / den);
  std::printf("modal at 10 ms against the FEM at 20 us: %.2e of the motion\n", error);
  EXPECT_LT(error, 1e-3);
  EXPECT_NEAR(b.t, 0.2, 1e-12);
}

// Each mode is an eigenpair of the FEM's own stiffness and mass: its
// Rayleigh quotient is its frequency squared, its modal mass one.
TEST(FemModal, ModesAreMassNormalisedEigenpairsOfTheStiffness) {
  const Mesh m = block();
  const Corotational f(m, solid(0), {});
  ModalOptions mo;
  mo.modes = 12;
  const Modal modal(f, mo);
  const Eigen::SparseMatrix<double> k = f.rest_stiffness();
  for (int i = 0; i < modal.modes(); ++i) {
    Eigen::Matrix3Xd phi = modal.shape(i);
    const Eigen::Map<const Eigen::VectorXd> p(phi.data(), phi.size());
    double mass = 0;
    for (int n = 0; n < m.size(); ++n) mass += f.mass()[n] * phi.col(n).squaredNorm();
    EXPECT_NEAR(mass, 1, 1e-9) << "mode " << i;
    const double w2 = modal.frequencies()[i] * modal.frequencies()[i];
    EXPECT_NEAR(p.dot(k * p), w2, 1e-9 * w2) << "mode " << i;
    if (i > 0) {
      EXPECT_GE(modal.frequencies()[i], modal.frequencies()[i - 1]);
    }
  }
}

// Undamped, at a step 1.5 times past the explicit limit of the highest
// mode (2 / w_max): a mode alone swings as a cos(w t), and a mix of modes
// keeps its energy.
TEST(FemModal, AnUndampedMotionIsExactAtAnyStep) {
  const Mesh m = block();
  const Corotational f(m, solid(0), {});
  const double w_max = Modal(f, ModalOptions{1e-3, free_dofs(m)}).frequencies().maxCoeff();
  ModalOptions mo;
  mo.dt = 3 / w_max, mo.modes = free_dofs(m);
  const Modal modal(f, mo);
  const int k = 3;
  const double a = 1e-4, w = modal.frequencies()[k];
  State s = rest_state(m);
  s.x += a * modal.shape(k);
  for (int n = 1; n <= 400; ++n) {
    modal.step(s, {});
    ASSERT_LT((s.x - m.rest - a * std::cos(w * n * mo.dt) * modal.shape(k)).cwiseAbs().maxCoeff(),
              1e-9 * a * modal.shape(k).cwiseAbs().maxCoeff())
        << "step " << n;
  }
  State mix = rest_state(m);
  mix.x += 1e-4 * (modal.shape(0) - 0.5 * modal.shape(5) + 0.25 * modal.shape(20));
  mix.v = 1e-2 * modal.shape(9);
  const double e0 = linear_energy(f, mix);
  for (int n = 0; n < 2000; ++n) modal.step(mix, {});
  EXPECT_NEAR(linear_energy(f, mix), e0, 1e-9 * e0);
}

// Damped and loaded long enough, with every mode: the displacement of a
// direct sparse solve of K u = f over the free nodes.
TEST(FemModal, WithEveryModeItSettlesWhereTheLinearSolveDoes) {
  const Mesh m = block();
  const Corotational f(m, solid(50), {});
  ModalOptions mo;
  mo.dt = 0.05, mo.modes = free_dofs(m);
  const Modal modal(f, mo);
  std::vector<PointForce> load = top_load(m, -1e-3);
  load.push_back({m.size() - 1, Eigen::Vector3d(2e-4, -1e-4, 0)});
  State s = rest_state(m);
  for (int n = 0; n < 400; ++n) modal.step(s, load);

  std::vector<int> dof(m.size(), -1), free;
  for (int i = 0; i < m.size(); ++i)
    if (!m.anchored[i]) dof[i] = 3 * int(free.size()), free.push_back(i);
  const Eigen::SparseMatrix<double> k = f.rest_stiffness();
  std::vector<Eigen::Triplet<double>> t;
  for (int col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
      if (dof[it.row() / 3] >= 0 && dof[it.col() / 3] >= 0)
        t.emplace_back(dof[it.row() / 3] + it.row() % 3, dof[it.col() / 3] + it.col() % 3, it.value());
  Eigen::SparseMatrix<double> kff(3 * free.size(), 3 * free.size());
  kff.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(kff.rows());
  for (const PointForce& p : load) rhs.segment<3>(dof[p.mass]) += p.force;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(kff);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd u = ldlt.solve(rhs);
  double num = 0, den = 0;
  for (std::size_t q = 0; q < free.size(); ++q) {
    num += (s.x.col(free[q]) - m.rest.col(free[q]) - u.segment<3>(3 * q)).squaredNorm();
    den += u.segment<3>(3 * q).squaredNorm();
  }
  EXPECT_LT(std::sqrt(num / den), 1e-8);
  for (int i = 0; i < m.size(); ++i)
    if (m.anchored[i]) {
      EXPECT_EQ(s.x.col(i), m.rest.col(i)) << "anchored node " << i;
    }
}

// Nothing anchored, undamped: a force held on one node carries the whole
// body as a rigid one, its centre of mass F t^2 / (2 M) along, through
// the six modes of no frequency.
TEST(FemModal, AFreeBodyIsCarriedByItsRigidModes) {
  const Mesh m = block(false);
  const Corotational f(m, solid(0), {});
  ModalOptions mo;
  mo.dt = 0.01, mo.modes = free_dofs(m);
  const Modal modal(f, mo);
  for (int i = 0; i < 6; ++i) EXPECT_LT(modal.frequencies()[i], 1e-5 * modal.frequencies()[6]) << "mode " << i;
  const Eigen::Vector3d force(1e-3, 0, 0);
  State s = rest_state(m);
  for (int n = 0; n < 50; ++n) modal.step(s, {{0, force}});
  const double total = f.mass().sum(), t = 50 * mo.dt;
  Eigen::Vector3d moved = Eigen::Vector3d::Zero();
  for (int i = 0; i < m.size(); ++i) moved += f.mass()[i] * (s.x.col(i) - m.rest.col(i)) / total;
  EXPECT_LT((moved - force * t * t / (2 * total)).norm(), 1e-9 * force.norm() * t * t / total);
}

void expect_named(const std::function<void()>& f, const std::string& words) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one naming '" << words << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

// The static displacement of one node under a force held on it: with
// every mode, the sparse solve's; with fewer, less (a Rayleigh-Ritz
// subspace is stiffer), and more so the fewer.
TEST(FemModal, ComplianceIsTheStaticSolvesWithEveryModeAndLessWithFewer) {
  const Mesh m = block();
  const Corotational f(m, solid(0), {});
  const int node = m.size() - 2, dofs = free_dofs(m);
  const Eigen::Vector3d force(1e-3, -2e-3, -5e-3);
  std::vector<int> dof(m.size(), -1), free;
  for (int i = 0; i < m.size(); ++i)
    if (!m.anchored[i]) dof[i] = 3 * int(free.size()), free.push_back(i);
  const Eigen::SparseMatrix<double> k = f.rest_stiffness();
  std::vector<Eigen::Triplet<double>> t;
  for (int col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
      if (dof[it.row() / 3] >= 0 && dof[it.col() / 3] >= 0)
        t.emplace_back(dof[it.row() / 3] + it.row() % 3, dof[it.col() / 3] + it.col() % 3, it.value());
  Eigen::SparseMatrix<double> kff(dofs, dofs);
  kff.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(dofs);
  rhs.segment<3>(dof[node]) = force;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(kff);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::Vector3d direct = ldlt.solve(rhs).segment<3>(dof[node]);
  const Eigen::Vector3d all = Modal(f, ModalOptions{1e-3, dofs}).compliance(node) * force;
  EXPECT_LT((all - direct).norm(), 1e-9 * direct.norm());
  double last = force.dot(all);
  for (const int modes : {40, 10, 3}) {
    const double work = force.dot(Modal(f, ModalOptions{1e-3, modes}).compliance(node) * force);
    EXPECT_GT(work, 0) << modes << " modes";
    EXPECT_LT(work, last) << modes << " modes";
    last = work;
  }
  expect_named([&] { (void)Modal(f, ModalOptions{1e-3, 4}).compliance(0); }, "no free node 0");
  const Corotational loose(block(false), solid(0), {});
  expect_named([&] { (void)Modal(loose, ModalOptions{1e-3, 8}).compliance(0); }, "6 kept modes have no stiffness");
}

TEST(FemModal, BadInputIsNamed) {
  const Mesh m = block();
  const Corotational f(m, solid(1), {});
  expect_named([&] { (void)Modal(f, ModalOptions{0, 4}); }, "dt");
  expect_named([&] { (void)Modal(f, ModalOptions{1e-3, 0}); }, "modes must be in 1.." + std::to_string(free_dofs(m)));
  expect_named([&] { (void)Modal(f, ModalOptions{1e-3, free_dofs(m) + 1}); }, "modes must be in");
  Mesh stuck = m;
  stuck.anchored.assign(m.size(), 1);
  expect_named([&] { (void)Modal(Corotational(stuck, solid(1), {}), ModalOptions{}); }, "no free node");
  const Modal modal(f, ModalOptions{1e-3, 4});
  State s = rest_state(m);
  expect_named([&] { modal.step(s, {{m.size(), Eigen::Vector3d::Zero()}}); }, "a load on node");
  expect_named([&] { modal.step(s, {{1, Eigen::Vector3d(std::nan(""), 0, 0)}}); }, "non-finite load");
  s.v(0, 5) = INFINITY;
  expect_named([&] { modal.step(s, {}); }, "the state must be finite");
  expect_named([&] { (void)modal.shape(4); }, "no mode 4");
}

}  // namespace
}  // namespace hcosim::models::fem
