// Adaptive active masses (001 §II.A): only masses with enough energy are
// simulated; activation spreads from the contact and retires when motion
// dies; the error against the full model shrinks with the threshold.
#include <set>

#include <gtest/gtest.h>

#include "models/massspring/simulator.h"

namespace hcosim::models::massspring {
namespace {

struct Scene {
  Lattice lattice;
  int contact = 0;
};

// A 12^3 box on its anchored floor, pressed at the middle of its top face.
Scene scene(double drag = 0.002) {
  Material m;
  m.b = 0.02;
  m.drag = drag;
  Scene s{make_box(12, 12, 12, 0.01, m), 0};
  anchor_where(s.lattice, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  s.contact = 6 + 12 * (6 + 12 * 11);
  return s;
}

// Press for `press` steps, release for `release`; returns the final state.
State run(Simulator& sim, int contact, int press, int release, int* max_simulated = nullptr) {
  State s = rest_state(sim.lattice());
  for (int k = 0; k < press + release; ++k) {
    const StepInfo info = sim.step(
        s, k < press ? std::vector<PointForce>{{contact, Eigen::Vector3d(0, 0, -0.3)}} : std::vector<PointForce>{});
    if (max_simulated) *max_simulated = std::max(*max_simulated, info.simulated);
  }
  return s;
}

double rel_error(const Lattice& l, const State& got, const State& ref) {
  return (got.x - ref.x).norm() / (ref.x - l.rest).norm();
}

TEST(MassspringAdaptive, ErrorShrinksWithTheThresholdAndSoDoesTheSaving) {
  const Scene sc = scene();
  Options o;
  o.integrator = Integrator::symplectic_euler;
  o.dt = 5e-4;
  Simulator full(sc.lattice, o);
  const State ref = run(full, sc.contact, 60, 0);
  double last_error = 1e9;
  int last_simulated = 0;
  for (double threshold : {1e-6, 1e-8, 1e-10, 1e-12}) {
    SCOPED_TRACE("threshold " + std::to_string(threshold));
    o.threshold = threshold;
    Simulator adaptive(sc.lattice, o);
    int simulated = 0;
    const State s = run(adaptive, sc.contact, 60, 0, &simulated);
    const double e = rel_error(sc.lattice, s, ref);
    EXPECT_LE(e, last_error);
    EXPECT_GE(simulated, last_simulated);
    last_error = e, last_simulated = simulated;
  }
  EXPECT_LT(last_error, 1e-3);
  // The loosest threshold simulates a small part of the box.
  o.threshold = 1e-6;
  Simulator loose(sc.lattice, o);
  int simulated = 0;
  run(loose, sc.contact, 60, 0, &simulated);
  EXPECT_LT(simulated, sc.lattice.size() / 3);
}

TEST(MassspringAdaptive, ActivationSpreadsFromTheContactAndRetires) {
  const Scene sc = scene(0.02);
  // The contact and the free masses it shares a spring with.
  std::set<int> ring{sc.contact};
  for (const Spring& sp : sc.lattice.springs)
    if (sp.i == sc.contact || sp.j == sc.contact) ring.insert(sp.i == sc.contact ? sp.j : sp.i);
  for (Integrator in : {Integrator::symplectic_euler, Integrator::implicit_euler, Integrator::local_global}) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    o.threshold = 1e-9;
    Simulator sim(sc.lattice, o);
    State s = rest_state(sc.lattice);
    const PointForce press{sc.contact, Eigen::Vector3d(0, 0, -0.3)};
    StepInfo first = sim.step(s, {press});
    EXPECT_EQ(first.simulated, int(ring.size()));
    StepInfo info;
    for (int k = 0; k < 20; ++k) info = sim.step(s, {press});
    EXPECT_GT(info.simulated, first.simulated);
    // Released, the damped box comes to rest and every mass retires.
    for (int k = 0; k < 3000 && info.active > 0; ++k) info = sim.step(s, {});
    EXPECT_EQ(info.active, 0);
    info = sim.step(s, {});
    EXPECT_EQ(info.simulated, 0);
  }
}

TEST(MassspringAdaptive, ZeroThresholdIsTheFullModel) {
  const Scene sc = scene();
  Options o;
  o.integrator = Integrator::velocity_verlet;
  Simulator full(sc.lattice, o);
  State s = rest_state(sc.lattice);
  const StepInfo info = full.step(s, {{sc.contact, Eigen::Vector3d(0, 0, -0.3)}});
  EXPECT_EQ(info.simulated, 12 * 12 * 11);
}

// The simulated set is kept up to date between steps, but the next state
// is still a function of the state and loads alone: a simulator that ran
// another state first, and one handed an edited State::quiet, give the
// same bits as a fresh one.
TEST(MassspringAdaptive, NextStateDependsOnlyOnStateAndLoads) {
  const Scene sc = scene();
  Options o;
  o.integrator = Integrator::symplectic_euler;
  o.dt = 5e-4;
  o.threshold = 1e-9;
  Simulator fresh(sc.lattice, o), used(sc.lattice, o);
  run(used, sc.contact + 5, 30, 30);
  const State a = run(fresh, sc.contact, 40, 40), b = run(used, sc.contact, 40, 40);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.v, b.v);
  EXPECT_EQ(a.quiet, b.quiet);
  // Waking every mass by hand: all of them are simulated next step.
  State c = a;
  std::fill(c.quiet.begin(), c.quiet.end(), 0);
  EXPECT_EQ(used.step(c, {}).simulated, 12 * 12 * 11);
}

}  // namespace
}  // namespace hcosim::models::massspring
