#include "models/massspring/simulator_impl.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace hcosim::models::massspring {

Simulator::Impl::Impl(Lattice l, const Options& o) : lat(std::move(l)), opt(o), adj(lat), quartet_index(lat) {
  const int n = lat.size();
  anchored = lat.anchored;
  held.assign(n, 0);
  inv_mass.resize(n);
  for (int i = 0; i < n; ++i) inv_mass[i] = lat.anchored[i] ? 0 : 1 / lat.mass[i];
  active.assign(n, 0);
  cover.assign(n, 0);
  slot.assign(n, -1);
  spring_slot.assign(lat.springs.size(), -1);
  ends.assign(lat.springs.size(), 0);
  quartet_slot.assign(lat.quartets.size(), -1);
  corners.assign(lat.quartets.size(), 0);
  quartet_force.setZero(3, 4 * lat.quartets.size());
  quartet_elastic.setZero(lat.quartets.size());
  for (auto* m : {&f, &x0, &v0, &sx, &sv}) m->setZero(3, n);
  elastic.setZero(n);
  spring_force.setZero(3, lat.springs.size());
  spring_elastic.setZero(lat.springs.size());
  adaptive = opt.threshold > 0;
  for (const Spring& sp : lat.springs) dampers = dampers || sp.b > 0;
  for (const Quartet& h : lat.quartets) dampers = dampers || h.b > 0;
  if (!adaptive) {
    for (int i = 0; i < n; ++i) enter(i);
    sort_lists();
  }
}

void Simulator::Impl::set_floors() {
  std::vector<std::uint8_t> always(lat.quartets.size());
  for (std::size_t q = 0; q < lat.quartets.size(); ++q) always[q] = lat.quartets[q].measure != Measure::volume;
  floors = std::isfinite(stable) && std::count(always.begin(), always.end(), 0) > 0;
  if (!floors) return;
  parts = spectrum_parts(lat, always);
  always_k = parts.quartet_k.size() ? parts.quartet_k.maxCoeff() : 0.0;
  always_b = parts.quartet_b.size() ? parts.quartet_b.maxCoeff() : 0.0;
  engage_at.assign(lat.quartets.size(), 0);
  shares.resize(lat.quartets.size());
  engaged.assign(lat.quartets.size(), 0);
  extra_k = extra_b = Eigen::VectorXd::Zero(lat.size());
  for (std::size_t q = 0; q < lat.quartets.size(); ++q) {
    if (always[q]) continue;
    Eigen::Vector3d g[4];
    engage_at[q] = lat.quartets[q].rest + kEngage * volume(lat.quartets[q], lat.rest, g);
    shares[q] = quartet_share(lat, lat.quartets[q]);
  }
}

bool Simulator::Impl::engage(const Eigen::Matrix3Xd& x, bool acting) {
  bool any = false;
  for (const int qi : quartets) {
    const Quartet& q = lat.quartets[qi];
    if (q.measure != Measure::volume || engaged[qi]) continue;
    const Eigen::Vector3d p0 = x.col(q.i);
    const double v = (x.col(q.j) - p0).dot((x.col(q.k) - p0).cross(x.col(q.l) - p0)) / 6;
    if (v < (acting ? q.rest : engage_at[qi])) engaged[qi] = 1, engaged_list.push_back(qi), any = true;
  }
  return any;
}

void Simulator::Impl::disengage() {
  for (const int qi : engaged_list) engaged[qi] = 0;
  engaged_list.clear();
}

int Simulator::Impl::engaged_substeps() {
  std::sort(engaged_list.begin(), engaged_list.end());
  for (const int qi : engaged_list) {
    const Quartet& q = lat.quartets[qi];
    const int c[4] = {q.i, q.j, q.k, q.l};
    for (int k = 0; k < 4; ++k) extra_k[c[k]] += shares[qi].k[k], extra_b[c[k]] += shares[qi].b[k];
  }
  double qk = always_k, qb = always_b;
  for (const int qi : engaged_list) {
    const Quartet& q = lat.quartets[qi];
    for (const int c : {q.i, q.j, q.k, q.l}) {
      qk = std::max(qk, parts.quartet_k[c] + extra_k[c]);
      qb = std::max(qb, parts.quartet_b[c] + extra_b[c]);
    }
  }
  for (const int qi : engaged_list) {
    const Quartet& q = lat.quartets[qi];
    for (const int c : {q.i, q.j, q.k, q.l}) extra_k[c] = extra_b[c] = 0;
  }
  const double h = models::massspring::stable_step(opt.integrator, parts.with_rows(qk, qb));
  return opt.dt > h ? std::min(substeps, int(std::ceil(opt.dt / h))) : 1;
}

void Simulator::Impl::set_substep(double h) {
  decay.resize(lat.size()), half.resize(lat.size());
  for (int i = 0; i < lat.size(); ++i) {
    decay[i] = std::exp(-h * lat.drag / lat.mass[i]);
    half[i] = std::exp(-0.5 * h * lat.drag / lat.mass[i]);
  }
}

// ---- explicit integrators, kept in the substep driver's translation unit:
// only there does the compiler inline their force loop into it, which the
// springs' step time rests on (bench massspring's step rows)

void Simulator::Impl::spring_energy(const Eigen::Matrix3Xd& x) {
  for (const int si : springs) {
    const Spring& sp = lat.springs[si];
    const double stretch = (x.col(sp.j) - x.col(sp.i)).norm() - sp.rest;
    spring_elastic[si] = 0.25 * sp.k * stretch * stretch;
  }
  for (const int qi : quartets) quartet_elastic[qi] = 0.5 * quartet_energy(lat.quartets[qi], x);
  for (const int i : masses) {
    elastic[i] = 0;
    for (int k = adj.start[i]; k < adj.start[i + 1]; ++k) elastic[i] += spring_elastic[adj.spring[k]];
    for (int k = quartet_index.start[i]; k < quartet_index.start[i + 1]; ++k)
      elastic[i] += quartet_elastic[quartet_index.quartet[k]];
  }
}

void Simulator::Impl::quartet_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool energy) {
  if (quartets.empty()) return;
  for (const int qi : quartets) {
    const Quartet& e = lat.quartets[qi];
    Eigen::Vector3d fq[4];
    const double d = models::massspring::quartet_forces(e, x, v, fq);
    for (int c = 0; c < 4; ++c) quartet_force.col(4 * qi + c) = fq[c];
    if (energy) quartet_elastic[qi] = 0.25 * e.stiffness * d * d;
  }
  for (const int i : masses)
    for (int k = quartet_index.start[i]; k < quartet_index.start[i + 1]; ++k) {
      const int qi = quartet_index.quartet[k];
      f.col(i) += quartet_force.col(4 * qi + quartet_index.corner[k]);
      if (energy) elastic[i] += quartet_elastic[qi];
    }
}

void Simulator::Impl::forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool with_drag) {
  for (const int i : masses) {
    f.col(i) = lat.mass[i] * lat.gravity;
    if (with_drag) f.col(i) -= lat.drag * v.col(i);
  }
  for (const PointForce& p : loads) f.col(p.mass) += p.force;
  if (dampers)
    adaptive ? spring_forces<true, true>(x, v) : spring_forces<true, false>(x, v);
  else
    adaptive ? spring_forces<false, true>(x, v) : spring_forces<false, false>(x, v);
  quartet_forces(x, v, adaptive);
  elastic_fresh = adaptive;
}

template <bool kDampers, bool kEnergy>
void Simulator::Impl::spring_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  const double* V = v.data();
  double* SF = spring_force.data();
  double* SE = spring_elastic.data();
  for (const int si : springs) {
    const Spring& s = lat.springs[si];
    const int a = 3 * s.i, b = 3 * s.j;
    double u[3];
    const double len = spring_axis(lat, s, x, u);
    const double stretch = len - s.rest;
    double mag = s.k * stretch;
    if (kDampers) mag += s.b * (u[0] * (V[b] - V[a]) + u[1] * (V[b + 1] - V[a + 1]) + u[2] * (V[b + 2] - V[a + 2]));
    SF[3 * si] = mag * u[0], SF[3 * si + 1] = mag * u[1], SF[3 * si + 2] = mag * u[2];
    if (kEnergy) SE[si] = 0.25 * s.k * stretch * stretch;
  }
  double* F = f.data();
  for (const int i : masses) {
    double sum[3] = {0, 0, 0}, e = 0;
    for (int k = adj.start[i]; k < adj.start[i + 1]; ++k) {
      const int si = adj.spring[k];
      const double sign = adj.sign[k];
      sum[0] += sign * SF[3 * si], sum[1] += sign * SF[3 * si + 1], sum[2] += sign * SF[3 * si + 2];
      if (kEnergy) e += SE[si];
    }
    F[3 * i] += sum[0], F[3 * i + 1] += sum[1], F[3 * i + 2] += sum[2];
    if (kEnergy) elastic[i] = e;
  }
}

void Simulator::Impl::symplectic_euler(State& s, double h) {
  forces(s.x, s.v, false);
  for (const int i : masses) {
    s.v.col(i) = (s.v.col(i) + h * inv_mass[i] * f.col(i)) * decay[i];
    s.x.col(i) += h * s.v.col(i);
  }
}

void Simulator::Impl::velocity_verlet(State& s, double h) {
  for (const int i : masses) s.v.col(i) *= half[i];
  forces(s.x, s.v, false);
  for (const int i : masses) {
    s.v.col(i) += 0.5 * h * inv_mass[i] * f.col(i);
    s.x.col(i) += h * s.v.col(i);
  }
  forces(s.x, s.v, false);
  for (const int i : masses) s.v.col(i) = (s.v.col(i) + 0.5 * h * inv_mass[i] * f.col(i)) * half[i];
}

void Simulator::Impl::rk4(State& s, double h) {
  for (const int i : masses) {
    x0.col(i) = s.x.col(i), v0.col(i) = s.v.col(i);
    sx.col(i).setZero(), sv.col(i).setZero();
  }
  static constexpr double share[4] = {1, 2, 2, 1}, reach[3] = {0.5, 0.5, 1.0};
  for (int stage = 0; stage < 4; ++stage) {
    forces(s.x, s.v, true);
    for (const int i : masses) {
      const Eigen::Vector3d kx = s.v.col(i), kv = inv_mass[i] * f.col(i);
      sx.col(i) += share[stage] * kx;
      sv.col(i) += share[stage] * kv;
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

// ---- one step

bool Simulator::Impl::substeps_of_step(State& s, int count, bool implicit, StepInfo& info) {
  const double h = opt.dt / count;
  for (int k = 0; k < count; ++k) {
    // An implicit substep moves every simulated mass at once: when the set
    // grows, it is taken again from its start with the grown set.
    if (adaptive && implicit) {
      ux.resize(3, masses.size()), uv.resize(3, masses.size());
      for (std::size_t q = 0; q < masses.size(); ++q) ux.col(q) = s.x.col(masses[q]), uv.col(q) = s.v.col(masses[q]);
    }
    for (;;) {
      switch (opt.integrator) {
        case Integrator::symplectic_euler:
          symplectic_euler(s, h);
          break;
        case Integrator::velocity_verlet:
          velocity_verlet(s, h);
          break;
        case Integrator::rk4:
          rk4(s, h);
          break;
        case Integrator::implicit_euler:
          info.solver_iterations += implicit_euler(s, h);
          break;
        case Integrator::local_global:
          local_global(s, h);
          break;
      }
      if (!adaptive || !s.x.allFinite() || !grow(s) || !implicit) break;
      // Back to the substep's start. grow() only appends to masses, and
      // the masses it added had not moved: they start where they are.
      const std::size_t had = std::size_t(ux.cols());
      for (std::size_t q = 0; q < had; ++q) s.x.col(masses[q]) = ux.col(q), s.v.col(masses[q]) = uv.col(q);
      ux.conservativeResize(3, masses.size()), uv.conservativeResize(3, masses.size());
      for (std::size_t q = had; q < masses.size(); ++q) ux.col(q) = s.x.col(masses[q]), uv.col(q) = s.v.col(masses[q]);
    }
    if (floors && engage(s.x, true) && engaged_substeps() > count) return false;
  }
  return true;
}

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
  if (!(o.dt > 0) || !std::isfinite(o.dt))
    throw std::invalid_argument("massspring: dt must be finite and > 0, got " + fmt(o.dt));
  if (o.max_substeps < 1) throw std::invalid_argument("massspring: max_substeps must be >= 1");
  if (o.iterations < 1) throw std::invalid_argument("massspring: iterations must be >= 1");
  if (!(o.tolerance > 0) || !(o.tolerance < 1)) throw std::invalid_argument("massspring: tolerance must be in (0, 1)");
  if (!std::isfinite(o.threshold)) throw std::invalid_argument("massspring: threshold must be finite");
  if (o.retire_steps < 1) throw std::invalid_argument("massspring: retire_steps must be >= 1");
  impl_ = std::make_unique<Impl>(std::move(lattice), o);
  Impl& m = *impl_;
  m.spectrum = bound_spectrum(m.lat);
  m.stable = models::massspring::stable_step(o.integrator, m.spectrum);
  if (o.dt > m.stable) {
    const double need = std::ceil(o.dt / m.stable);
    const std::string why = std::string(name(o.integrator)) + ": dt " + fmt(o.dt) + " s exceeds the stable step " +
                            fmt(m.stable) + " s (omega_max <= " + fmt(m.spectrum.omega_max) +
                            " rad/s, damping <= " + fmt(m.spectrum.damping_max) + " 1/s; quartets alone " +
                            fmt(m.spectrum.quartet_omega_max) + " rad/s, " + fmt(m.spectrum.quartet_damping_max) +
                            " 1/s)";
    // local_global steps only its quartets explicitly: implicit_euler is what is left.
    const std::string other =
        o.integrator == Integrator::local_global ? "use implicit_euler" : "use implicit_euler or local_global";
    if (o.on_unstable == OnUnstable::refuse)
      throw std::invalid_argument(why + "; substep (" + fmt(need) + " substeps), use a smaller dt, or " + other);
    if (need > o.max_substeps)
      throw std::invalid_argument(why + "; it needs " + fmt(need) + " substeps, more than max_substeps " +
                                  std::to_string(o.max_substeps) + "; " + other);
    m.substeps = int(need);
  }
  m.set_floors();
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
    if (!p.force.allFinite())
      throw std::invalid_argument("massspring: non-finite load on mass " + std::to_string(p.mass));
  }
  m.select(s, loads);
  m.back_up(s);
  StepInfo info;
  int count = m.substeps;
  if (m.floors) {
    m.disengage();
    m.engage(s.x, false);
    count = m.engaged_substeps();
  }
  const bool implicit = !is_explicit(m.opt.integrator);
  // Taken again from its start, with more substeps, when a floor that was
  // not counted pushes during it.
  for (bool again = true; again;) {
    again = false;
    if (m.substep_of != count) m.set_substep(m.opt.dt / count), m.substep_of = count;
    info.substeps = count;
    if (m.substeps_of_step(s, count, implicit, info)) break;
    m.restore(s);
    count = m.engaged_substeps(), again = true;
  }
  if (!(m.whole && s.x.allFinite() && s.v.allFinite()))
    for (const int i : m.masses)
      if (!s.x.col(i).allFinite() || !s.v.col(i).allFinite()) {
        m.restore(s);
        throw std::runtime_error(std::string("massspring: ") + name(m.opt.integrator) +
                                 " produced a non-finite state at mass " + std::to_string(i) + ", t = " + fmt(s.t) +
                                 " s; the state is left as before the step");
      }
  s.t += m.opt.dt;
  info.simulated = int(m.masses.size());
  info.active = m.adaptive ? m.retire(s) : info.simulated;
  return info;
}

void Simulator::hold(int i, bool on) {
  Impl& m = *impl_;
  if (i < 0 || i >= m.lat.size())
    throw std::invalid_argument("massspring: cannot hold mass " + std::to_string(i) + ", lattice has " +
                                std::to_string(m.lat.size()));
  if (m.anchored[i])
    throw std::invalid_argument("massspring: mass " + std::to_string(i) + " is anchored, not free to hold");
  m.hold(i, on);
}

bool Simulator::held(int i) const { return i >= 0 && i < impl_->lat.size() && impl_->held[i]; }

Eigen::Vector3d Simulator::spring_force(int i, const State& s) const {
  const Impl& m = *impl_;
  if (i < 0 || i >= m.lat.size() || s.x.cols() != m.lat.size() || s.v.cols() != m.lat.size())
    throw std::invalid_argument("massspring: spring_force of mass " + std::to_string(i) + " in a state of " +
                                std::to_string(s.x.cols()) + " masses, lattice has " + std::to_string(m.lat.size()));
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int e = m.adj.start[i]; e < m.adj.start[i + 1]; ++e) {
    double u[3];
    const double mag = spring_tension(m.lat, m.lat.springs[m.adj.spring[e]], s.x, s.v, u);
    f += m.adj.sign[e] * mag * Eigen::Vector3d(u[0], u[1], u[2]);
  }
  for (int e = m.quartet_index.start[i]; e < m.quartet_index.start[i + 1]; ++e) {
    Eigen::Vector3d fh[4];
    models::massspring::quartet_forces(m.lat.quartets[m.quartet_index.quartet[e]], s.x, s.v, fh);
    f += fh[m.quartet_index.corner[e]];
  }
  return f;
}

const Lattice& Simulator::lattice() const { return impl_->lat; }
const Options& Simulator::options() const { return impl_->opt; }
const Spectrum& Simulator::spectrum() const { return impl_->spectrum; }
double Simulator::stable_step() const { return impl_->stable; }
int Simulator::substeps() const { return impl_->substeps; }

}  // namespace hcosim::models::massspring
