#include "models/massspring/simulator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include "models/massspring/quartet.h"

namespace hcosim::models::massspring {

// Index of a lattice: for every mass, its springs and the mass at their other end.
struct Adjacency {
  std::vector<int> start;    // n + 1 offsets into spring / other
  std::vector<int> spring;   // incident spring indices
  std::vector<int> other;    // the other end of each
  std::vector<double> sign;  // +1 where the mass is the spring's first end, else -1

  explicit Adjacency(const Lattice& l) : start(l.size() + 1, 0) {
    for (const Spring& s : l.springs) ++start[s.i + 1], ++start[s.j + 1];
    for (int i = 0; i < l.size(); ++i) start[i + 1] += start[i];
    spring.resize(start.back());
    other.resize(start.back());
    sign.resize(start.back());
    std::vector<int> at(start.begin(), start.end() - 1);
    for (int si = 0; si < int(l.springs.size()); ++si) {
      const Spring& s = l.springs[si];
      spring[at[s.i]] = si, sign[at[s.i]] = 1, other[at[s.i]++] = s.j;
      spring[at[s.j]] = si, sign[at[s.j]] = -1, other[at[s.j]++] = s.i;
    }
  }
};

// For every mass, the quartets it is a corner of and which corner (0-3).
struct QuartetIndex {
  std::vector<int> start;    // n + 1 offsets
  std::vector<int> quartet;  // incident quartet indices, in lattice order
  std::vector<int> corner;   // the mass's corner in each

  explicit QuartetIndex(const Lattice& l) : start(l.size() + 1, 0) {
    auto corners = [](const Quartet& h) { return std::array<int, 4>{h.i, h.j, h.k, h.l}; };
    for (const Quartet& h : l.quartets)
      for (const int c : corners(h)) ++start[c + 1];
    for (int i = 0; i < l.size(); ++i) start[i + 1] += start[i];
    quartet.resize(start.back());
    corner.resize(start.back());
    std::vector<int> at(start.begin(), start.end() - 1);
    for (int qi = 0; qi < int(l.quartets.size()); ++qi) {
      const auto c = corners(l.quartets[qi]);
      for (int q = 0; q < 4; ++q) quartet[at[c[q]]] = qi, corner[at[c[q]]++] = q;
    }
  }
};

struct Simulator::Impl {
  Lattice lat;
  Options opt;
  Adjacency adj;
  QuartetIndex quartet_index;
  Spectrum spectrum;  // every quartet counted: the worst case
  double stable = 0;
  int substeps = 1;
  int substep_of = 0;  // the substeps per step that decay and half are for

  // Volume floors count in a step's stable step only while engaged: from
  // when their volume comes within kEngage of their rest volume above the
  // floor, or when one acts before that within a step (the step is then
  // taken again). At rest none acts, and a lattice's floors would
  // otherwise cost every step the substeps of all of them pressed at once
  // (5 instead of 1 for the default hybrid at 1 kHz, at 0d8f102).
  static constexpr double kEngage = 0.25;
  bool floors = false;                // whether engagement can change the substeps
  SpectrumParts parts;                // springs and the quartets always counted
  double always_k = 0, always_b = 0;  // the largest of parts' quartet rows
  std::vector<double> engage_at;      // m^3 per quartet, for the floors
  std::vector<QuartetShare> shares;   // per quartet, for the floors
  std::vector<std::uint8_t> engaged;  // per quartet
  std::vector<int> engaged_list;      // the engaged floors
  Eigen::VectorXd extra_k, extra_b;   // scratch rows, zero between uses
  bool adaptive = false;
  bool dampers = false;                      // whether any spring has b > 0
  std::vector<double> inv_mass;              // 1/kg, 0 for anchored and held masses
  std::vector<std::uint8_t> anchored, held;  // the lattice's own anchors; held by the caller
  std::vector<double> decay, half;           // exact drag decay over a substep and half of one

  // The simulated set, kept up to date as masses activate and retire
  // rather than rebuilt each step: active masses, every free mass within
  // one spring of one (`cover` counts the active masses in its closed
  // neighbourhood), and the springs (and quartets) with at least one
  // simulated end (corner).
  std::vector<std::uint8_t> active;
  std::vector<int> cover;
  std::vector<int> masses, slot;            // simulated masses; mass -> index in masses, or -1
  std::vector<int> springs, spring_slot;    // their springs; spring -> index in springs, or -1
  std::vector<std::uint8_t> ends;           // simulated ends of each spring
  std::vector<int> quartets, quartet_slot;  // as springs and spring_slot
  std::vector<std::uint8_t> corners;        // simulated corners of each quartet
  std::vector<int> seen_quiet;              // State::quiet as the last step left it
  std::size_t moved = 0;                    // masses that entered or left since the lists were sorted
  std::vector<PointForce> loads;            // this step's loads on simulated masses

  Eigen::Matrix3Xd f, x0, v0, sx, sv;  // scratch, 3 x n; f of masses outside the set is unused
  Eigen::Matrix3Xd bx, bv;             // the step's starting point, per mass of `backed`
  std::vector<int> backed;             // the masses bx and bv hold (all of them when `whole`)
  bool whole = false;
  Eigen::Matrix3Xd ux, uv;          // an implicit substep's starting point, per simulated mass
  std::vector<int> grown;           // scratch: masses grow() activates
  Eigen::VectorXd elastic;          // J, half the elastic energy of each mass's springs
  bool elastic_fresh = false;       // whether the last force pass filled `elastic`
  Eigen::Matrix3Xd spring_force;    // N, per spring, on its first end
  Eigen::VectorXd spring_elastic;   // J, a quarter of each spring's energy
  Eigen::Matrix3Xd quartet_force;   // N, per quartet, on its corners i, j, k, l (4 columns each)
  Eigen::VectorXd quartet_elastic;  // J, half of each quartet's energy

  // implicit_euler. Its matrix is refilled in place while the simulated
  // masses, springs and quartets are those it was built for: building it
  // from triplets every step cost as much as solving it.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  Eigen::VectorXd dv;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::SparseMatrix<double> step_a;
  std::vector<int> step_value;                                // step_a's value index of each triplet
  std::vector<int> step_masses, step_springs, step_quartets;  // what step_a was built for

  // local_global: the factorization and the masses it was made for.
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt;
  std::vector<int> factored;
  Eigen::MatrixX3d base, rhs, delta;

  // lat.anchored is the union of the lattice's anchors and the held masses.
  Impl(Lattice l, const Options& o) : lat(std::move(l)), opt(o), adj(lat), quartet_index(lat) {
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

  // Floors and their shares, once the spectrum's worst case is known.
  void set_floors() {
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

  // Engages the simulated floors whose volume at x is below engage_at (or,
  // if `acting`, below their rest: they push). Returns whether any did.
  bool engage(const Eigen::Matrix3Xd& x, bool acting) {
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

  void disengage() {
    for (const int qi : engaged_list) engaged[qi] = 0;
    engaged_list.clear();
  }

  // Substeps per step for the springs, hinges and engaged floors, each
  // floor's share summed in lattice order.
  int engaged_substeps() {
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

  void set_substep(double h) {
    decay.resize(lat.size()), half.resize(lat.size());
    for (int i = 0; i < lat.size(); ++i) {
      decay[i] = std::exp(-h * lat.drag / lat.mass[i]);
      half[i] = std::exp(-0.5 * h * lat.drag / lat.mass[i]);
    }
  }

  // ---- simulated set

  void enter(int i) {
    if (lat.anchored[i]) return;
    slot[i] = int(masses.size()), masses.push_back(i);
    ++moved;
    for (int e = adj.start[i]; e < adj.start[i + 1]; ++e) {
      const int si = adj.spring[e];
      if (ends[si]++ == 0) spring_slot[si] = int(springs.size()), springs.push_back(si);
    }
    for (int e = quartet_index.start[i]; e < quartet_index.start[i + 1]; ++e) {
      const int qi = quartet_index.quartet[e];
      if (corners[qi]++ == 0) quartet_slot[qi] = int(quartets.size()), quartets.push_back(qi);
    }
  }

  // A mass that leaves the set stops where it is.
  void leave(int i, State& s) {
    if (slot[i] < 0) return;
    remove(i);
    s.v.col(i).setZero();
  }

  void remove(int i) {
    const int k = slot[i];
    masses[k] = masses.back(), slot[masses[k]] = k, masses.pop_back();
    ++moved;
    slot[i] = -1;
    for (int e = adj.start[i]; e < adj.start[i + 1]; ++e) {
      const int si = adj.spring[e];
      if (--ends[si] > 0) continue;
      const int q = spring_slot[si];
      springs[q] = springs.back(), spring_slot[springs[q]] = q, springs.pop_back();
      spring_slot[si] = -1;
    }
    for (int e = quartet_index.start[i]; e < quartet_index.start[i + 1]; ++e) {
      const int qi = quartet_index.quartet[e];
      if (--corners[qi] > 0) continue;
      const int q = quartet_slot[qi];
      quartets[q] = quartets.back(), quartet_slot[quartets[q]] = q, quartets.pop_back();
      quartet_slot[qi] = -1;
    }
  }

  void hold(int i, bool on) {
    if (held[i] == on) return;
    held[i] = on;
    lat.anchored[i] = on;
    inv_mass[i] = on ? 0 : 1 / lat.mass[i];
    if (on) {
      if (slot[i] >= 0) remove(i);
      if (adaptive && !active[i]) activate(i);
    } else if (!adaptive || cover[i] > 0) {
      enter(i);
    }
  }

  void activate(int i) {
    active[i] = 1;
    if (cover[i]++ == 0) enter(i);
    for (int e = adj.start[i]; e < adj.start[i + 1]; ++e)
      if (cover[adj.other[e]]++ == 0) enter(adj.other[e]);
  }

  void deactivate(int i, State& s) {
    active[i] = 0;
    if (--cover[i] == 0) leave(i, s);
    for (int e = adj.start[i]; e < adj.start[i + 1]; ++e)
      if (--cover[adj.other[e]] == 0) leave(adj.other[e], s);
  }

  // The set for this step: unchanged since the last one unless the caller
  // edited State::quiet (or passed another state), then rebuilt from it.
  void select(State& s, const std::vector<PointForce>& in) {
    if (adaptive) {
      if (s.quiet != seen_quiet) {
        leave_all();
        std::fill(active.begin(), active.end(), 0);
        std::fill(cover.begin(), cover.end(), 0);
        for (int i = 0; i < lat.size(); ++i)
          if (held[i] || (!lat.anchored[i] && s.quiet[i] < opt.retire_steps)) activate(i);
        seen_quiet = s.quiet;
      }
      for (const PointForce& p : in)
        if (!lat.anchored[p.mass] && p.force.squaredNorm() > 0) {
          s.quiet[p.mass] = seen_quiet[p.mass] = 0;
          if (!active[p.mass]) activate(p.mass);
        }
    }
    // Entering and leaving scatter the lists; back in lattice order once an
    // eighth of them moved, so that the force loop walks memory forward.
    if (moved * 8 > masses.size()) sort_lists();
    loads.clear();
    for (const PointForce& p : in)
      if (slot[p.mass] >= 0) loads.push_back(p);
  }

  void sort_lists() {
    std::sort(masses.begin(), masses.end());
    std::sort(springs.begin(), springs.end());
    std::sort(quartets.begin(), quartets.end());
    for (int k = 0; k < int(masses.size()); ++k) slot[masses[k]] = k;
    for (int k = 0; k < int(springs.size()); ++k) spring_slot[springs[k]] = k;
    for (int k = 0; k < int(quartets.size()); ++k) quartet_slot[quartets[k]] = k;
    moved = 0;
  }

  // Empties the set without touching any state.
  void leave_all() {
    for (const int i : masses) slot[i] = -1;
    for (const int si : springs) spring_slot[si] = -1, ends[si] = 0;
    for (const int qi : quartets) quartet_slot[qi] = -1, corners[qi] = 0;
    masses.clear(), springs.clear(), quartets.clear();
  }

  // Backs up what the step changes, restored if it fails: whole matrices
  // when most masses are simulated, as contiguous copies are faster.
  void back_up(const State& s) {
    whole = 2 * masses.size() > std::size_t(lat.size());
    backed.clear();
    if (whole) {
      bx = s.x, bv = s.v;
      return;
    }
    bx.resize(3, masses.size()), bv.resize(3, masses.size());
    for (const int i : masses) back_up(i, s);
  }
  void back_up(int i, const State& s) {
    if (whole) return;
    const int k = int(backed.size());
    if (k >= bx.cols()) bx.conservativeResize(3, 2 * k + 1), bv.conservativeResize(3, 2 * k + 1);
    bx.col(k) = s.x.col(i), bv.col(k) = s.v.col(i);
    backed.push_back(i);
  }
  void restore(State& s) const {
    if (whole) {
      s.x = bx, s.v = bv;
      return;
    }
    for (std::size_t k = 0; k < backed.size(); ++k) s.x.col(backed[k]) = bx.col(k), s.v.col(backed[k]) = bv.col(k);
  }

  // The adaptive set grows within a step: a simulated mass that is not yet
  // active but moved in the last substep with kinetic energy above the
  // threshold is activated, so that its neighbours join the set for the
  // next substep (or, for an implicit one, for the same substep again).
  // Without this the set grew one ring per step whatever moved inside it,
  // and the error against the full model stopped falling with the
  // threshold. Returns whether the set grew.
  bool grow(State& s) {
    grown.clear();
    for (const int i : masses)
      if (!active[i] && 0.5 * lat.mass[i] * s.v.col(i).squaredNorm() > opt.threshold) grown.push_back(i);
    const std::size_t before = masses.size();
    for (const int i : grown) {
      s.quiet[i] = seen_quiet[i] = 0;
      activate(i);
    }
    for (std::size_t k = before; k < masses.size(); ++k) back_up(masses[k], s);
    // The last force pass left the entering springs' energies stale.
    if (!grown.empty()) elastic_fresh = false;
    return !grown.empty();
  }

  // Energy bookkeeping of the adaptive model after a step: a simulated mass
  // above threshold is active; one below it for retire_steps steps retires.
  int retire(State& s) {
    if (!elastic_fresh) spring_energy(s.x);
    std::vector<int> on, off;
    int count = 0;
    for (const int i : masses) {
      const double e = 0.5 * lat.mass[i] * s.v.col(i).squaredNorm() + elastic[i];
      int& q = s.quiet[i];
      if (e > opt.threshold) {
        q = 0;
        if (!active[i]) on.push_back(i);
      } else if (q < opt.retire_steps && ++q == opt.retire_steps && active[i]) {
        off.push_back(i);
      }
      seen_quiet[i] = q;
      count += q < opt.retire_steps;
    }
    for (const int i : on) activate(i);
    for (const int i : off) deactivate(i, s);
    return count;
  }

  // `elastic` from the springs and quartets at x, for integrators without a
  // force pass.
  void spring_energy(const Eigen::Matrix3Xd& x) {
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

  // Adds the quartets' forces at (x, v) to f for the simulated masses, each
  // summing its quartets in lattice order (as spring_forces does), and their
  // energy shares to `elastic` if `energy`.
  void quartet_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool energy) {
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

  // ---- explicit integrators

  // f = spring, gravity and point forces on the simulated masses, and drag
  // if `with_drag`; the adaptive model also gets each mass's elastic energy.
  void forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool with_drag) {
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

  // The hot loop of every explicit integrator, on raw column-major arrays.
  // Each spring's force is computed once, then each mass sums its springs
  // in the lattice's fixed order, so that the result does not depend on the
  // order in which masses joined the set. No relative velocity is needed
  // where no spring has a damper.
  template <bool kDampers, bool kEnergy>
  void spring_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
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

  // Symplectic Euler; drag, linear and per mass, is integrated exactly.
  void symplectic_euler(State& s, double h) {
    forces(s.x, s.v, false);
    for (const int i : masses) {
      s.v.col(i) = (s.v.col(i) + h * inv_mass[i] * f.col(i)) * decay[i];
      s.x.col(i) += h * s.v.col(i);
    }
  }

  // Velocity Verlet inside a Strang splitting with the exact drag flow, so
  // that drag keeps second order; spring dampers act at the half-step velocity.
  void velocity_verlet(State& s, double h) {
    for (const int i : masses) s.v.col(i) *= half[i];
    forces(s.x, s.v, false);
    for (const int i : masses) {
      s.v.col(i) += 0.5 * h * inv_mass[i] * f.col(i);
      s.x.col(i) += h * s.v.col(i);
    }
    forces(s.x, s.v, false);
    for (const int i : masses) s.v.col(i) = (s.v.col(i) + 0.5 * h * inv_mass[i] * f.col(i)) * half[i];
  }

  void rk4(State& s, double h) {
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

  // ---- implicit Euler, linearised

  const Eigen::SparseMatrix<double>& step_matrix(const Eigen::Matrix3Xd& x, double h) {
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

  int implicit_euler(State& s, double h) {
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
    if (llt.info() != Eigen::Success)
      throw std::runtime_error("local_global: the system matrix is not positive definite");
    factored = masses;
  }

  // Quartets are not in the prefactored matrix: their forces at the step's
  // start join the external ones (explicit), so a stiff quartet limits the
  // step as it would symplectic_euler's.
  void local_global(State& s, double h) {
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

  // ---- one step

  // `count` substeps of the step. Returns false, at once, when a floor
  // that was not counted pushed during one and needs more (it is engaged
  // now).
  bool substeps_of_step(State& s, int count, bool implicit, StepInfo& info) {
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
        for (std::size_t q = had; q < masses.size(); ++q)
          ux.col(q) = s.x.col(masses[q]), uv.col(q) = s.v.col(masses[q]);
      }
      if (floors && engage(s.x, true) && engaged_substeps() > count) return false;
    }
    return true;
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
