#include "massspring/simulator.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

namespace hcosim::massspring {

// Index of a lattice: for every mass, its springs and the mass at their other end.
struct Adjacency {
  std::vector<int> start;   // n + 1 offsets into spring / other
  std::vector<int> spring;  // incident spring indices
  std::vector<int> other;   // the other end of each

  explicit Adjacency(const Lattice& l) : start(l.size() + 1, 0) {
    for (const Spring& s : l.springs) ++start[s.i + 1], ++start[s.j + 1];
    for (int i = 0; i < l.size(); ++i) start[i + 1] += start[i];
    spring.resize(start.back());
    other.resize(start.back());
    std::vector<int> at(start.begin(), start.end() - 1);
    for (int si = 0; si < int(l.springs.size()); ++si) {
      const Spring& s = l.springs[si];
      spring[at[s.i]] = si, other[at[s.i]++] = s.j;
      spring[at[s.j]] = si, other[at[s.j]++] = s.i;
    }
  }
};

struct Simulator::Impl {
  Lattice lat;
  Options opt;
  Adjacency adj;
  Spectrum spectrum;
  double stable = 0;
  int substeps = 1;
  bool adaptive = false;

  // The simulated set of this step: masses integrated, springs acting on
  // them, every mass those springs touch, and the loads on simulated masses.
  std::vector<int> masses, springs, touched;
  std::vector<PointForce> loads;
  std::vector<int> slot;                       // mass -> index in masses, or -1
  std::vector<std::uint8_t> spring_mark, touch_mark, keep;

  Eigen::Matrix3Xd f, a, x0, v0, sx, sv;      // scratch, 3 x n
  Eigen::Matrix3Xd bx, bv;                    // the step's starting point, per simulated mass

  // implicit_euler
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  Eigen::VectorXd dv;

  // local_global: the factorization and the masses it was made for.
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt;
  std::vector<int> factored;
  Eigen::MatrixX3d base, rhs, delta;

  Impl(Lattice l, const Options& o) : lat(std::move(l)), opt(o), adj(lat) {
    const int n = lat.size();
    slot.assign(n, -1);
    spring_mark.assign(lat.springs.size(), 0);
    touch_mark.assign(n, 0);
    keep.assign(n, 0);
    for (auto* m : {&f, &a, &x0, &v0, &sx, &sv}) m->setZero(3, n);
    adaptive = opt.threshold > 0;
  }

  // ---- simulated set

  void select(State& s, const std::vector<PointForce>& in) {
    for (const PointForce& p : in)
      if (!lat.anchored[p.mass] && p.force.squaredNorm() > 0) s.quiet[p.mass] = 0;
    std::vector<int> next;
    if (!adaptive) {
      if (masses.empty())
        for (int i = 0; i < lat.size(); ++i)
          if (!lat.anchored[i]) next.push_back(i);
    } else {
      // Active masses are always simulated ones or newly loaded ones.
      auto add = [&](int i) {
        if (!lat.anchored[i] && !keep[i]) keep[i] = 1, next.push_back(i);
      };
      std::vector<int> seeds;
      for (const int i : masses)
        if (s.quiet[i] < opt.retire_steps) seeds.push_back(i);
      for (const PointForce& p : in)
        if (!lat.anchored[p.mass] && s.quiet[p.mass] < opt.retire_steps) seeds.push_back(p.mass);
      for (const int i : seeds) {
        add(i);
        for (int e = adj.start[i]; e < adj.start[i + 1]; ++e) add(adj.other[e]);
      }
      // Masses that leave the set stop where they are.
      for (const int i : masses)
        if (!keep[i]) s.v.col(i).setZero();
      for (const int i : next) keep[i] = 0;
    }
    if (!next.empty() || adaptive) rebuild(next);
    loads.clear();
    for (const PointForce& p : in)
      if (slot[p.mass] >= 0) loads.push_back(p);
  }

  void rebuild(std::vector<int>& next) {
    for (const int i : masses) slot[i] = -1;
    masses.swap(next);
    for (int k = 0; k < int(masses.size()); ++k) slot[masses[k]] = k;
    for (const int si : springs) spring_mark[si] = 0;
    for (const int i : touched) touch_mark[i] = 0;
    springs.clear();
    touched.clear();
    auto touch = [&](int i) {
      if (!touch_mark[i]) touch_mark[i] = 1, touched.push_back(i);
    };
    for (const int i : masses)
      for (int e = adj.start[i]; e < adj.start[i + 1]; ++e) {
        const int si = adj.spring[e];
        if (!spring_mark[si]) spring_mark[si] = 1, springs.push_back(si);
        touch(i);
        touch(adj.other[e]);
      }
    for (const int i : masses) touch(i);
  }

  // Energy bookkeeping of the adaptive model after a step.
  int retire(State& s) const {
    int active = 0;
    for (const int i : masses) {
      double e = 0.5 * lat.mass[i] * s.v.col(i).squaredNorm();
      for (int k = adj.start[i]; k < adj.start[i + 1]; ++k) {
        const Spring& sp = lat.springs[adj.spring[k]];
        const double stretch = (s.x.col(sp.j) - s.x.col(sp.i)).norm() - sp.rest;
        e += 0.25 * sp.k * stretch * stretch;
      }
      if (e > opt.threshold) s.quiet[i] = 0;
      else if (s.quiet[i] < opt.retire_steps) ++s.quiet[i];
      active += s.quiet[i] < opt.retire_steps;
    }
    return active;
  }

  // ---- explicit integrators

  // a = M^-1 f(x, v) on the simulated masses.
  void accel(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
    for (const int i : touched) f.col(i).setZero();
    add_forces(lat, springs, masses, loads, x, v, f);
    for (const int i : masses) a.col(i) = f.col(i) / lat.mass[i];
  }

  void symplectic_euler(State& s, double h) {
    accel(s.x, s.v);
    for (const int i : masses) {
      s.v.col(i) += h * a.col(i);
      s.x.col(i) += h * s.v.col(i);
    }
  }

  void velocity_verlet(State& s, double h) {
    accel(s.x, s.v);
    for (const int i : masses) {
      s.v.col(i) += 0.5 * h * a.col(i);
      s.x.col(i) += h * s.v.col(i);
    }
    accel(s.x, s.v);
    for (const int i : masses) s.v.col(i) += 0.5 * h * a.col(i);
  }

  void rk4(State& s, double h) {
    for (const int i : masses) {
      x0.col(i) = s.x.col(i), v0.col(i) = s.v.col(i);
      sx.col(i).setZero(), sv.col(i).setZero();
    }
    static constexpr double weight[4] = {1, 2, 2, 1}, reach[3] = {0.5, 0.5, 1.0};
    for (int stage = 0; stage < 4; ++stage) {
      accel(s.x, s.v);
      for (const int i : masses) {
        const Eigen::Vector3d kx = s.v.col(i), kv = a.col(i);
        sx.col(i) += weight[stage] * kx;
        sv.col(i) += weight[stage] * kv;
        if (stage < 3) {
          s.x.col(i) = x0.col(i) + reach[stage] * h * kx;
          s.v.col(i) = v0.col(i) + reach[stage] * h * kv;
        }
      }
    }
    for (const int i : masses) {
      s.x.col(i) = x0.col(i) + h / 6 * sx.col(i);
      s.v.col(i) = v0.col(i) + h / 6 * sv.col(i);
    }
  }

  // ---- implicit Euler, linearised

  int implicit_euler(State& s, double h) {
    const int m = int(masses.size());
    for (const int i : touched) f.col(i).setZero();
    add_forces(lat, springs, masses, loads, s.x, s.v, f);
    add_stiffness_times(lat, springs, s.x, s.v, -h, f);
    Eigen::VectorXd b(3 * m);
    for (int k = 0; k < m; ++k) b.segment<3>(3 * k) = h * f.col(masses[k]);
    const Eigen::SparseMatrix<double> A = implicit_matrix(lat, springs, masses, slot, s.x, h);
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

  // ---- local/global (Liu, O'Brien, Kavan, Kim 2013)

  void factor(double h) {
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
    if (llt.info() != Eigen::Success) throw std::runtime_error("local_global: the system matrix is not positive definite");
    factored = masses;
  }

  void local_global(State& s, double h) {
    if (factored != masses) factor(h);
    const int m = int(masses.size());
    base.resize(m, 3);
    delta.resize(m, 3);
    for (const int i : touched) x0.col(i) = s.x.col(i);
    for (int k = 0; k < m; ++k) {
      const int i = masses[k];
      Eigen::Vector3d ext = lat.mass[i] * lat.gravity;
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
        const Eigen::RowVector3d e = h * h * sp.k * (x0.col(sp.i) - x0.col(sp.j) - d).transpose();
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
};

namespace {

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(3);
  o << v;
  return o.str();
}

}  // namespace

State rest_state(const Lattice& l) {
  State s;
  s.x = l.rest;
  s.v.setZero(3, l.size());
  s.quiet.assign(l.size(), std::numeric_limits<int>::max() / 2);
  return s;
}

Simulator::Simulator(Lattice lattice, const Options& o) {
  check(lattice);
  if (!(o.dt > 0) || !std::isfinite(o.dt)) throw std::invalid_argument("massspring: dt must be finite and > 0, got " + fmt(o.dt));
  if (o.max_substeps < 1) throw std::invalid_argument("massspring: max_substeps must be >= 1");
  if (o.iterations < 1) throw std::invalid_argument("massspring: iterations must be >= 1");
  if (!(o.tolerance > 0) || !(o.tolerance < 1)) throw std::invalid_argument("massspring: tolerance must be in (0, 1)");
  if (!std::isfinite(o.threshold)) throw std::invalid_argument("massspring: threshold must be finite");
  if (o.retire_steps < 1) throw std::invalid_argument("massspring: retire_steps must be >= 1");
  impl_ = std::make_unique<Impl>(std::move(lattice), o);
  Impl& m = *impl_;
  m.spectrum = bound_spectrum(m.lat);
  m.stable = massspring::stable_step(o.integrator, m.spectrum);
  if (o.dt > m.stable) {
    const double need = std::ceil(o.dt / m.stable);
    const std::string why = std::string(name(o.integrator)) + ": dt " + fmt(o.dt) + " s exceeds the stable step " +
                            fmt(m.stable) + " s (omega_max <= " + fmt(m.spectrum.omega_max) +
                            " rad/s, damping <= " + fmt(m.spectrum.damping_max) + " 1/s)";
    if (o.on_unstable == OnUnstable::refuse)
      throw std::invalid_argument(why + "; substep (" + fmt(need) +
                                  " substeps), use a smaller dt, or use implicit_euler or local_global");
    if (need > o.max_substeps)
      throw std::invalid_argument(why + "; it needs " + fmt(need) + " substeps, more than max_substeps " +
                                  std::to_string(o.max_substeps) + "; use implicit_euler or local_global");
    m.substeps = int(need);
  }
}

Simulator::~Simulator() = default;

StepInfo Simulator::step(State& s, const std::vector<PointForce>& loads) {
  Impl& m = *impl_;
  const int n = m.lat.size();
  if (s.x.cols() != n || s.v.cols() != n || int(s.quiet.size()) != n)
    throw std::invalid_argument("massspring: state has " + std::to_string(s.x.cols()) + " masses, lattice " +
                                std::to_string(n));
  for (const PointForce& p : loads) {
    if (p.mass < 0 || p.mass >= n)
      throw std::invalid_argument("massspring: load on mass " + std::to_string(p.mass) + ", lattice has " +
                                  std::to_string(n));
    if (!p.force.allFinite()) throw std::invalid_argument("massspring: non-finite load on mass " + std::to_string(p.mass));
  }
  m.select(s, loads);
  // Backup of what the step changes, restored if it fails.
  Eigen::Matrix3Xd &bx = m.bx, &bv = m.bv;
  bx.resize(3, m.masses.size()), bv.resize(3, m.masses.size());
  for (std::size_t k = 0; k < m.masses.size(); ++k) bx.col(k) = s.x.col(m.masses[k]), bv.col(k) = s.v.col(m.masses[k]);
  StepInfo info;
  info.substeps = m.substeps;
  const double h = m.opt.dt / m.substeps;
  for (int k = 0; k < m.substeps; ++k) switch (m.opt.integrator) {
      case Integrator::symplectic_euler: m.symplectic_euler(s, h); break;
      case Integrator::velocity_verlet: m.velocity_verlet(s, h); break;
      case Integrator::rk4: m.rk4(s, h); break;
      case Integrator::implicit_euler: info.solver_iterations += m.implicit_euler(s, h); break;
      case Integrator::local_global: m.local_global(s, h); break;
    }
  for (const int i : m.masses)
    if (!s.x.col(i).allFinite() || !s.v.col(i).allFinite()) {
      for (std::size_t k = 0; k < m.masses.size(); ++k) s.x.col(m.masses[k]) = bx.col(k), s.v.col(m.masses[k]) = bv.col(k);
      throw std::runtime_error(std::string("massspring: ") + name(m.opt.integrator) + " produced a non-finite state at mass " +
                               std::to_string(i) + ", t = " + fmt(s.t) + " s; the state is left as before the step");
    }
  s.t += m.opt.dt;
  info.simulated = int(m.masses.size());
  info.active = m.adaptive ? m.retire(s) : info.simulated;
  return info;
}

const Lattice& Simulator::lattice() const { return impl_->lat; }
const Options& Simulator::options() const { return impl_->opt; }
const Spectrum& Simulator::spectrum() const { return impl_->spectrum; }
double Simulator::stable_step() const { return impl_->stable; }
int Simulator::substeps() const { return impl_->substeps; }

}  // namespace hcosim::massspring
