// Held masses (the hybrid model's moved chains, the stylus's contact
// vertex): kinematic under every integrator, their neighbours simulated,
// and the reaction they pass on equal to the springs' static force.
#include <gtest/gtest.h>

#include "models/massspring/simulator.h"

namespace hcosim::models::massspring {
namespace {

// anchor - free - held along x, springs k = 50 N/m, 1 cm long.
Lattice line() {
  Lattice l;
  l.rest.resize(3, 3);
  l.rest << 0, 0.01, 0.02, 0, 0, 0, 0, 0, 0;
  l.mass = Eigen::Vector3d::Constant(1e-3);
  l.springs = {{0, 1, 0.01, 50, 0.02}, {1, 2, 0.01, 50, 0.02}};
  l.anchored = {1, 0, 0};
  l.drag = 0.01;
  return l;
}

TEST(MassspringHold, HeldMassStaysAndPassesTheSeriesSpringForce) {
  for (Integrator in : {Integrator::symplectic_euler, Integrator::velocity_verlet, Integrator::rk4,
                        Integrator::implicit_euler, Integrator::local_global})
    for (double threshold : {0.0, 1e-12}) {
      SCOPED_TRACE(std::string(name(in)) + " threshold " + std::to_string(threshold));
      Options o;
      o.integrator = in;
      o.threshold = threshold;
      Simulator sim(line(), o);
      State s = rest_state(sim.lattice());
      const double d = 0.004;  // m, pulled along +x
      s.x(0, 2) += d;
      sim.hold(2, true);
      EXPECT_TRUE(sim.held(2));
      for (int k = 0; k < 3000; ++k) sim.step(s, {});
      EXPECT_EQ(s.x(0, 2), 0.02 + d);              // exactly where it was put
      EXPECT_NEAR(s.x(0, 1), 0.01 + d / 2, 1e-7);  // the free mass settles midway
      // Two springs in series: k/2 on the whole pull, back toward the anchor.
      EXPECT_NEAR(sim.spring_force(2, s).x(), -25 * d, 1e-5);
      EXPECT_NEAR(sim.spring_force(2, s).tail<2>().norm(), 0, 1e-12);

      sim.hold(2, false);
      for (int k = 0; k < 3000; ++k) sim.step(s, {});
      EXPECT_NEAR(s.x(0, 2), 0.02, 1e-6);  // released, it springs back
    }
}

TEST(MassspringHold, HoldingWakesTheNeighboursOfTheAdaptiveModel) {
  Lattice l = make_box(6, 6, 6, 0.01, Material{});
  anchor_where(l, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  Options o;
  o.integrator = Integrator::symplectic_euler;
  o.threshold = 1e-9;
  Simulator sim(l, o);
  State s = rest_state(l);
  const int top = 3 + 6 * (3 + 6 * 5);
  s.x(2, top) -= 0.003;
  sim.hold(top, true);
  const StepInfo info = sim.step(s, {});
  EXPECT_GT(info.simulated, 0);
  const int below = 3 + 6 * (3 + 6 * 4);
  for (int k = 0; k < 50; ++k) sim.step(s, {});
  EXPECT_LT(s.x(2, below), l.rest(2, below) - 1e-4);  // pushed down by the held mass
  EXPECT_EQ(s.x(2, top), l.rest(2, top) - 0.003);
}

TEST(MassspringHold, RefusesMissingAndAnchoredMasses) {
  Simulator sim(line(), Options{});
  EXPECT_THROW(sim.hold(3, true), std::invalid_argument);
  EXPECT_THROW(sim.hold(-1, true), std::invalid_argument);
  EXPECT_THROW(sim.hold(0, true), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::massspring
