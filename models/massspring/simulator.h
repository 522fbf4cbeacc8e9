// The behavior model (000 eq 8-13, 001 eq 2, 001 §II.A): integrates
// M x'' + D x' + K x = F(t) for a lattice, optionally only over its active
// masses. Deterministic: the same lattice, options, state and loads give the
// same next state.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "models/massspring/forces.h"
#include "models/massspring/integrator.h"
#include "models/massspring/lattice.h"

namespace hcosim::models::massspring {

// What an explicit integrator does when dt exceeds its stable step.
enum class OnUnstable { substep, refuse };

struct Options {
  Integrator integrator = Integrator::implicit_euler;
  double dt = 1e-3;  // s, > 0
  OnUnstable on_unstable = OnUnstable::substep;
  int max_substeps = 1000;  // more than this is refused
  int iterations = 10;      // local_global: iterations per step
  double tolerance = 1e-8;  // implicit_euler: CG relative residual
  // Adaptive active masses (001 §II.A, Fig 2): a mass whose kinetic energy
  // plus half the elastic energy of its springs exceeds `threshold` (J), or
  // that carries a point force, is active; it and its neighbours are
  // simulated, every other mass is held still. A mass retires after
  // `retire_steps` steps below the threshold. threshold <= 0 simulates all.
  double threshold = 0;
  int retire_steps = 10;
};

// Positions and velocities of every mass (anchored ones included) and, for
// the adaptive model, how many steps each mass has been below threshold.
struct State {
  Eigen::Matrix3Xd x;  // m
  Eigen::Matrix3Xd v;  // m/s
  double t = 0;        // s
  std::vector<int> quiet;
};

// At rest in the lattice's rest configuration, every mass inactive.
State rest_state(const Lattice& lattice);

struct StepInfo {
  int substeps = 1;           // explicit integrators: steps of dt / substeps this step took
  int simulated = 0;          // masses integrated (active ones and their neighbours)
  int active = 0;             // masses above threshold after the step
  int solver_iterations = 0;  // implicit_euler: CG iterations, summed over substeps
};

class Simulator {
 public:
  // Throws std::invalid_argument for a bad lattice or option, and when an
  // explicit integrator's dt exceeds its stable step with
  // on_unstable = refuse or by more than max_substeps times.
  Simulator(Lattice lattice, const Options& options);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  // Advances `state` by options().dt under `loads`. Throws
  // std::invalid_argument for a state of the wrong size or a load on a
  // missing mass or with a non-finite force, and std::runtime_error if the
  // state ever became non-finite (it is then left as before the step).
  StepInfo step(State& state, const std::vector<PointForce>& loads);

  // Holds or releases a free mass. A held mass is kinematic: steps leave it
  // where the State puts it (its velocity there drives the spring dampers),
  // as the moved chains of the hybrid model and the stylus's contact vertex
  // need; in the adaptive model it counts as active, so its neighbours are
  // simulated. Throws std::invalid_argument for a missing or anchored mass.
  void hold(int mass, bool held);
  bool held(int mass) const;

  // N: the net spring and damper force on `mass` in `state`. A held mass at
  // rest passes it whole to what holds it: it is the force on the stylus.
  Eigen::Vector3d spring_force(int mass, const State& state) const;

  const Lattice& lattice() const;  // its anchors include the held masses
  const Options& options() const;
  // With every quartet counted: a step counts each volume floor only
  // while the state brings it near its floor (docs/massspring.md, "Volume
  // floors"), so it takes at most substeps() substeps (StepInfo::substeps).
  const Spectrum& spectrum() const;
  double stable_step() const;  // s; +infinity for implicit integrators
  int substeps() const;        // per step of dt, at most

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hcosim::models::massspring
