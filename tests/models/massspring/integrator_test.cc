// Each integrator against known answers: a damped oscillator's discrete
// frequency and damping, the order of its error, static deflections,
// momentum, the spectrum bound, and the implicit matrix against finite
// differences.
#include <cmath>
#include <complex>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

#include "models/massspring/simulator.h"
#include "tests/support/integrators.h"

namespace hcosim::models::massspring {
namespace {

using Complex = std::complex<double>;

// One mass on a spring of rest length 1 m to an anchor, moving along x;
// damped by the spring's damper b or by air friction `drag` (N s/m).
Lattice oscillator(double m, double k, double b, double drag = 0) {
  Lattice l;
  l.rest.resize(3, 2);
  l.rest << 0, 1, 0, 0, 0, 0;
  l.mass = Eigen::Vector2d(1, m);
  l.anchored = {1, 0};
  l.springs = {{0, 1, 1.0, k, b}};
  l.drag = drag;
  return l;
}

// The one-step map of the oscillator x'' = -w^2 x - c x' under each
// integrator, derived from its definition in integrator.h, with c from a
// spring damper or (`drag`) from air friction, which symplectic_euler and
// velocity_verlet integrate exactly; returns the eigenvalue with positive
// imaginary part (or the larger real one).
Complex theory(Integrator in, double w, double c, double h, bool drag = false) {
  const Complex lambda = (-c + std::sqrt(Complex(c * c - 4 * w * w))) / 2.0;
  if (in == Integrator::rk4) {
    const Complex z = lambda * h;
    return 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
  }
  if (in == Integrator::implicit_euler || in == Integrator::local_global) return 1.0 / (1.0 - h * lambda);
  const double b = drag ? 0 : c, full = drag ? std::exp(-c * h) : 1, half = drag ? std::exp(-c * h / 2) : 1;
  auto acc = [&](double x, double v) { return -w * w * x - b * v; };
  Eigen::Matrix2d map;
  for (int col = 0; col < 2; ++col) {
    double x = col == 0, v = col == 1;
    if (in == Integrator::symplectic_euler) {
      v = (v + h * acc(x, v)) * full;
      x += h * v;
    } else {  // velocity_verlet: spring damping at the half-step velocity
      v *= half;
      v += h / 2 * acc(x, v);
      x += h * v;
      v += h / 2 * acc(x, v);
      v *= half;
    }
    map.col(col) << x, v;
  }
  const Eigen::Vector2cd e = map.eigenvalues();
  return e[0].imag() > 0 || (e[0].imag() == 0 && std::abs(e[0]) > std::abs(e[1])) ? e[0] : e[1];
}

// Simulates the oscillator from a 0.1 m stretch and recovers the one-step
// eigenvalue from the positions: x[n+2] = 2 Re(z) x[n+1] - |z|^2 x[n],
// fitted by least squares over the whole run.
Complex measured(Integrator in, double w, double c, double h, int steps, bool drag = false) {
  Options o;
  o.integrator = in;
  o.dt = h;
  o.on_unstable = OnUnstable::refuse;
  o.iterations = 3;
  o.tolerance = 1e-13;
  Simulator sim(drag ? oscillator(1.0, w * w, 0, c) : oscillator(1.0, w * w, c), o);
  State s = rest_state(sim.lattice());
  s.x(0, 1) = 1.1;
  std::vector<double> x{0.1};
  for (int k = 0; k < steps; ++k) {
    sim.step(s, {});
    x.push_back(s.x(0, 1) - 1.0);
  }
  Eigen::MatrixX2d a(steps - 1, 2);
  Eigen::VectorXd y(steps - 1);
  for (int n = 0; n + 2 <= steps; ++n) {
    a.row(n) << x[n + 1], x[n];
    y[n] = x[n + 2];
  }
  const Eigen::Vector2d pq = a.colPivHouseholderQr().solve(y);
  const double re = pq[0] / 2, mod2 = -pq[1];
  return re * re <= mod2 ? Complex(re, std::sqrt(mod2 - re * re)) : Complex(re + std::sqrt(re * re - mod2), 0);
}

// Discrete angular frequency (rad/s) and decay rate (1/s) of eigenvalue z.
double frequency(Complex z, double h) { return std::arg(z) / h; }
double decay(Complex z, double h) { return -std::log(std::abs(z)) / h; }

struct Mode {
  double w, zeta, h;
};

class MassspringAccuracyPerIntegrator : public ::testing::TestWithParam<Integrator> {};

TEST_P(MassspringAccuracyPerIntegrator, OscillatorMatchesItsTheory) {
  const Integrator in = GetParam();
  for (const bool drag : {false, true})
    for (const Mode cs : {Mode{10, 0.0, 0.01}, Mode{10, 0.05, 0.01}, Mode{10, 0.3, 0.02}, Mode{40, 0.1, 0.02}}) {
      SCOPED_TRACE("w " + std::to_string(cs.w) + " zeta " + std::to_string(cs.zeta) + (drag ? " drag" : " damper"));
      const double c = 2 * cs.zeta * cs.w;
      const Complex zt = theory(in, cs.w, c, cs.h, drag), zm = measured(in, cs.w, c, cs.h, 300, drag);
      EXPECT_NEAR(frequency(zm, cs.h), frequency(zt, cs.h), 1e-6 * cs.w);
      EXPECT_NEAR(decay(zm, cs.h), decay(zt, cs.h), 1e-6 * cs.w);
    }
}

// Air friction is linear and per mass and both symplectic maps keep phase
// space volume, so symplectic_euler and velocity_verlet (by Strang
// splitting) damp at exactly the drag's rate: |z|^2 = e^(-c h) at any h.
TEST(MassspringAccuracy, DragDecayIsExact) {
  const double w = 10, c = 2 * 0.05 * w;
  for (Integrator in : {Integrator::symplectic_euler, Integrator::velocity_verlet})
    for (const double h : {0.02, 0.1}) {
      SCOPED_TRACE(std::string(name(in)) + " h " + std::to_string(h));
      EXPECT_NEAR(decay(measured(in, w, c, h, 400, true), h), c / 2, 1e-9);
    }
}

// Frequency and damping errors against the exact oscillator shrink at each
// integrator's order: halving h divides the error by 2^p. Frequency is
// measured undamped; decay with zeta = 0.05.
TEST(MassspringAccuracy, ErrorsShrinkAtTheTheoreticalOrder) {
  const double w = 10, c = 2 * 0.05 * w;
  struct Order {
    Integrator in;
    double freq_p, decay_p, h;
  };
  // Symplectic Euler: frequency second order, damping first order (its
  // |z|^2 = 1 - c h). Verlet: frequency second order; damping first order,
  // as it is evaluated at the half-step velocity. RK4: fourth order.
  // Implicit Euler: second order in frequency, first in damping (it adds
  // w^2 h / 2). RK4's leading damping term nearly cancels at this zeta, so
  // it is measured at smaller steps where the h^4 term dominates.
  for (const Order o : {Order{Integrator::symplectic_euler, 2, 1, 0.02}, Order{Integrator::velocity_verlet, 2, 1, 0.02},
                        Order{Integrator::rk4, 4, 4, 0.005}, Order{Integrator::implicit_euler, 2, 1, 0.02}}) {
    SCOPED_TRACE(name(o.in));
    const double h = o.h;
    const double f1 = frequency(measured(o.in, w, 0, h, 400), h) - w;
    const double f2 = frequency(measured(o.in, w, 0, h / 2, 800), h / 2) - w;
    const double d1 = decay(measured(o.in, w, c, h, 400), h) - c / 2;
    const double d2 = decay(measured(o.in, w, c, h / 2, 800), h / 2) - c / 2;
    EXPECT_NEAR(std::log2(std::abs(f1 / f2)), o.freq_p, 0.15);
    EXPECT_NEAR(std::log2(std::abs(d1 / d2)), o.decay_p, 0.15);
  }
}

// A vertical chain hanging from an anchor under gravity: spring s carries
// the weight of the masses below it, so its stretch is that weight over k.
TEST_P(MassspringAccuracyPerIntegrator, HangingChainMatchesTheExactStaticDeflection) {
  const Integrator in = GetParam();
  const int n = 8;
  const double m = 0.01, k = 20, spacing = 0.05, g = 9.81;
  Lattice l;
  l.rest.setZero(3, n + 1);
  for (int i = 0; i <= n; ++i) l.rest(2, i) = -spacing * i;
  l.mass.setConstant(n + 1, m);
  l.anchored.assign(n + 1, 0);
  l.anchored[0] = 1;
  for (int i = 0; i < n; ++i) l.springs.push_back({i, i + 1, spacing, k, 0.05});
  l.gravity << 0, 0, -g;
  l.drag = 0.05;  // settles in seconds
  Options o;
  o.integrator = in;
  o.dt = 1e-3;
  o.iterations = 20;
  o.tolerance = 1e-12;
  Simulator sim(l, o);
  State s = rest_state(l);
  for (int step = 0; step < 20000; ++step) sim.step(s, {});
  double z = 0;
  for (int i = 1; i <= n; ++i) {
    z -= spacing + (n - i + 1) * m * g / k;
    EXPECT_NEAR(s.x(2, i), z, 1e-9) << "mass " << i;
  }
}

// A sheet hanging in its own plane from its top edge under gravity: the
// dynamic model at rest agrees with the linear static solve K u = F. (A
// flat sheet has no linear stiffness across its plane, so the load is in
// the plane.)
TEST(MassspringAccuracy, HangingSheetMatchesTheLinearSolve) {
  Material mat;
  mat.mass = 1e-4, mat.k = 500, mat.b = 0.05, mat.drag = 0.01;
  Lattice l = make_sheet(6, 5, 0.02, mat);
  std::fill(l.anchored.begin(), l.anchored.end(), 0);
  anchor_where(l, [](const Eigen::Vector3d& p) { return p.y() > 0.079; });
  l.gravity << 0, -9.81, 0;
  Options o;
  o.integrator = Integrator::implicit_euler;
  o.dt = 2e-3;
  o.tolerance = 1e-13;
  Simulator sim(l, o);
  State s = rest_state(l);
  for (int step = 0; step < 10000; ++step) sim.step(s, {});
  // Linear solve on the free masses' in-plane coordinates with the
  // rest-state stiffness. implicit_matrix(h) = M + h C + h^2 K, so
  // K = (A(2h) - 2 A(h) + M) / 2h^2 exactly.
  std::vector<int> masses, slot(l.size(), -1), springs;
  for (int i = 0; i < l.size(); ++i)
    if (!l.anchored[i]) slot[i] = int(masses.size()), masses.push_back(i);
  for (int si = 0; si < int(l.springs.size()); ++si) springs.push_back(si);
  const double h = 1.0;
  const Eigen::MatrixXd M = Eigen::MatrixXd(implicit_matrix(l, {}, {}, masses, slot, l.rest, 0.0));
  const Eigen::MatrixXd K = (Eigen::MatrixXd(implicit_matrix(l, springs, {}, masses, slot, l.rest, 2 * h)) -
                             2 * Eigen::MatrixXd(implicit_matrix(l, springs, {}, masses, slot, l.rest, h)) + M) /
                            (2 * h * h);
  const int m = int(masses.size());
  Eigen::MatrixXd Kp(2 * m, 2 * m);
  Eigen::VectorXd F(2 * m);
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b < m; ++b) Kp.block<2, 2>(2 * a, 2 * b) = K.block<2, 2>(3 * a, 3 * b);
    F.segment<2>(2 * a) = l.mass[masses[a]] * l.gravity.head<2>();
  }
  const Eigen::VectorXd u = Kp.ldlt().solve(F);
  double max_u = 0, max_err = 0;
  for (int a = 0; a < m; ++a) {
    const Eigen::Vector3d got = s.x.col(masses[a]) - l.rest.col(masses[a]);
    max_u = std::max(max_u, u.segment<2>(2 * a).norm());
    max_err = std::max(max_err, (got.head<2>() - u.segment<2>(2 * a)).norm());
    EXPECT_EQ(got.z(), 0.0);
  }
  // Small load (sag well under 1% of the spacing): the geometric
  // nonlinearity is below 1% of the deflection.
  EXPECT_GT(max_u, 1e-6);
  EXPECT_LT(max_u, 2e-4);
  EXPECT_LT(max_err, 0.01 * max_u);
}

// bound_spectrum is an upper bound of the true highest eigenfrequency, at
// rest and deformed, and on the semi-sphere its spring-wise bound is far
// tighter than the mass-wise one: sqrt(2 deg k / m) at the 32-spring pole
// is 1.95 times the true frequency, the spring-wise bound under 1.5 times.
TEST(MassspringAccuracy, SpectrumBoundIsAboveTheTrueHighestFrequency) {
  Material mat;
  mat.k = 50, mat.mass = 1e-3;
  Lattice box = make_box(4, 4, 4, 0.01, mat);
  anchor_where(box, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  for (const Lattice& l : {make_sheet(6, 5, 0.01, mat), make_semisphere(6, 32, 0.1, mat), box}) {
    std::vector<int> masses, slot(l.size(), -1), springs;
    for (int i = 0; i < l.size(); ++i)
      if (!l.anchored[i]) slot[i] = int(masses.size()), masses.push_back(i);
    for (int si = 0; si < int(l.springs.size()); ++si) springs.push_back(si);
    const double bound = bound_spectrum(l).omega_max;
    std::srand(7);
    for (const double stretch : {0.0, 0.5}) {
      const Eigen::Matrix3Xd x = l.rest + stretch * 0.01 * Eigen::Matrix3Xd::Random(3, l.size());
      const Eigen::MatrixXd M = Eigen::MatrixXd(implicit_matrix(l, {}, {}, masses, slot, x, 0.0));
      const Eigen::MatrixXd K = (Eigen::MatrixXd(implicit_matrix(l, springs, {}, masses, slot, x, 2.0)) -
                                 2 * Eigen::MatrixXd(implicit_matrix(l, springs, {}, masses, slot, x, 1.0)) + M) /
                                2;
      const Eigen::VectorXd r = M.diagonal().cwiseInverse().cwiseSqrt();
      const Eigen::MatrixXd A = r.asDiagonal() * K * r.asDiagonal();
      const double truth = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff());
      SCOPED_TRACE(std::to_string(l.size()) + " masses, stretch " + std::to_string(stretch));
      EXPECT_GE(bound, truth);
      if (l.size() == 6 * 32 + 1) {
        EXPECT_LT(bound, 1.5 * truth);
      }
    }
  }
}

// No external force: internal forces come in opposite pairs, so momentum
// is kept to rounding by every integrator.
TEST_P(MassspringAccuracyPerIntegrator, MomentumIsConservedWithoutExternalForce) {
  const Integrator in = GetParam();
  Material mat;
  mat.b = 0.01;
  Lattice l = make_box(4, 3, 3, 0.01, mat);
  l.mass[5] = 0.01;  // unequal masses
  Eigen::Matrix3Xd v0 = Eigen::Matrix3Xd::Zero(3, l.size());
  for (int i = 0; i < l.size(); ++i) v0.col(i) << std::sin(i), std::cos(3 * i), 0.5 * std::sin(7 * i);
  Options o;
  o.integrator = in;
  o.dt = 1e-3;
  o.tolerance = 1e-14;  // implicit_euler conserves it to the CG residual
  Simulator sim(l, o);
  State s = rest_state(l);
  s.v = 0.1 * v0;
  const Eigen::Vector3d p0 = momentum(l, s.v);
  for (int step = 0; step < 300; ++step) sim.step(s, {});
  EXPECT_LT((momentum(l, s.v) - p0).norm(), 1e-12 * (1 + p0.norm()));
  EXPECT_GT((s.x - l.rest).norm(), 1e-4);  // it did move
}

INSTANTIATE_TEST_SUITE_P(, MassspringAccuracyPerIntegrator, ::testing::ValuesIn(tests::kIntegrators),
                         tests::integrator_name);

// The implicit matrix's K and C are the derivatives of the forces.
TEST(MassspringAccuracy, ImplicitMatrixIsTheForceJacobian) {
  Material mat;
  mat.k = 30, mat.b = 0.2;
  Lattice l = make_box(3, 2, 2, 0.01, mat);
  // Every spring stretched (compressed ones drop their geometric term).
  Eigen::Matrix3Xd x = 1.05 * l.rest, v = Eigen::Matrix3Xd::Zero(3, l.size());
  for (int i = 0; i < l.size(); ++i)
    x.col(i) += 1e-4 * Eigen::Vector3d(std::sin(2 * i), std::cos(5 * i), std::sin(i + 1));
  std::vector<int> masses, slot, springs;
  for (int i = 0; i < l.size(); ++i) masses.push_back(i), slot.push_back(i);
  for (int si = 0; si < int(l.springs.size()); ++si) springs.push_back(si);
  const double h = 1.0;
  const Eigen::MatrixXd M = Eigen::MatrixXd(implicit_matrix(l, {}, {}, masses, slot, x, 0.0));
  const Eigen::MatrixXd A1 = Eigen::MatrixXd(implicit_matrix(l, springs, {}, masses, slot, x, h));
  const Eigen::MatrixXd A2 = Eigen::MatrixXd(implicit_matrix(l, springs, {}, masses, slot, x, 2 * h));
  const Eigen::MatrixXd K = (A2 - 2 * A1 + M) / (2 * h * h), Cd = (A1 - M) / h - h * K;
  auto force = [&](const Eigen::Matrix3Xd& xx, const Eigen::Matrix3Xd& vv) {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, l.size());
    add_forces(l, springs, {}, {}, {}, xx, vv, f);
    return Eigen::Map<const Eigen::VectorXd>(f.data(), f.size()).eval();
  };
  const double eps = 1e-7;
  for (int col = 0; col < 3 * l.size(); ++col) {
    Eigen::Matrix3Xd xp = x, xm = x, vp = v, vm = v;
    xp.data()[col] += eps, xm.data()[col] -= eps, vp.data()[col] += eps, vm.data()[col] -= eps;
    const Eigen::VectorXd dfx = -(force(xp, v) - force(xm, v)) / (2 * eps);
    const Eigen::VectorXd dfv = -(force(x, vp) - force(x, vm)) / (2 * eps);
    EXPECT_LT((K.col(col) - dfx).norm(), 1e-5 * mat.k) << "column " << col;
    EXPECT_LT((Cd.col(col) - dfv).norm(), 1e-6) << "column " << col;
  }
}

}  // namespace
}  // namespace hcosim::models::massspring
