// The mass-spring simulator's working state and the steps that share it:
// simulator.cc (set-up, volume floors, a step's substeps and the explicit
// integrators), active_set.cc (the adaptive model's simulated set) and
// implicit_step.cc (the implicit integrators). Not an API: use simulator.h.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include "models/massspring/integrator.h"
#include "models/massspring/quartet.h"
#include "models/massspring/simulator.h"

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
  // otherwise cost every step the substeps of all of them pressed at once.
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
  Impl(Lattice l, const Options& o);

  // Floors and their shares, once the spectrum's worst case is known.
  void set_floors();

  // Engages the simulated floors whose volume at x is below engage_at (or,
  // if `acting`, below their rest: they push). Returns whether any did.
  bool engage(const Eigen::Matrix3Xd& x, bool acting);

  void disengage();

  // Substeps per step for the springs, hinges and engaged floors, each
  // floor's share summed in lattice order.
  int engaged_substeps();

  void set_substep(double h);

  // ---- simulated set

  void enter(int i);

  // A mass that leaves the set stops where it is.
  void leave(int i, State& s);

  void remove(int i);
  void hold(int i, bool on);
  void activate(int i);
  void deactivate(int i, State& s);

  // The set for this step: unchanged since the last one unless the caller
  // edited State::quiet (or passed another state), then rebuilt from it.
  void select(State& s, const std::vector<PointForce>& in);

  void sort_lists();

  // Empties the set without touching any state.
  void leave_all();

  // Backs up what the step changes, restored if it fails: whole matrices
  // when most masses are simulated, as contiguous copies are faster.
  void back_up(const State& s);
  void back_up(int i, const State& s);
  void restore(State& s) const;

  // The adaptive set grows within a step: a simulated mass that is not yet
  // active but moved in the last substep with kinetic energy above the
  // threshold is activated, so that its neighbours join the set for the
  // next substep (or, for an implicit one, for the same substep again).
  // Without this the set grew one ring per step whatever moved inside it,
  // and the error against the full model stopped falling with the
  // threshold. Returns whether the set grew.
  bool grow(State& s);

  // Energy bookkeeping of the adaptive model after a step: a simulated mass
  // above threshold is active; one below it for retire_steps steps retires.
  int retire(State& s);

  // `elastic` from the springs and quartets at x, for integrators without a
  // force pass.
  void spring_energy(const Eigen::Matrix3Xd& x);

  // Adds the quartets' forces at (x, v) to f for the simulated masses, each
  // summing its quartets in lattice order (as spring_forces does), and their
  // energy shares to `elastic` if `energy`.
  void quartet_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool energy);

  // ---- explicit integrators

  // f = spring, gravity and point forces on the simulated masses, and drag
  // if `with_drag`; the adaptive model also gets each mass's elastic energy.
  void forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool with_drag);

  // The hot loop of every explicit integrator, on raw column-major arrays.
  // Each spring's force is computed once, then each mass sums its springs
  // in the lattice's fixed order, so that the result does not depend on the
  // order in which masses joined the set. No relative velocity is needed
  // where no spring has a damper.
  template <bool kDampers, bool kEnergy>
  void spring_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v);

  // Symplectic Euler; drag, linear and per mass, is integrated exactly.
  void symplectic_euler(State& s, double h);

  // Velocity Verlet inside a Strang splitting with the exact drag flow, so
  // that drag keeps second order; spring dampers act at the half-step velocity.
  void velocity_verlet(State& s, double h);
  void rk4(State& s, double h);

  // ---- implicit Euler, linearised

  const Eigen::SparseMatrix<double>& step_matrix(const Eigen::Matrix3Xd& x, double h);
  int implicit_euler(State& s, double h);

  // ---- local/global (Liu, O'Brien, Kavan, Kim 2013)

  void factor(double h);

  // Quartets are not in the prefactored matrix: their forces at the step's
  // start join the external ones (explicit), so a stiff quartet limits the
  // step as it would symplectic_euler's.
  void local_global(State& s, double h);

  // ---- one step

  // `count` substeps of the step. Returns false, at once, when a floor
  // that was not counted pushed during one and needs more (it is engaged
  // now).
  bool substeps_of_step(State& s, int count, bool implicit, StepInfo& info);
};

}  // namespace hcosim::models::massspring
