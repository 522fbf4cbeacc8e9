// Numerical stability on hard cases: every run must stay finite, keep its
// energy bounded by what was put in, and do what physics says.
#include <cmath>

#include <gtest/gtest.h>

#include "models/massspring/simulator.h"

namespace hcosim::models::massspring {
namespace {

const Integrator kAll[] = {Integrator::symplectic_euler, Integrator::velocity_verlet, Integrator::rk4,
                           Integrator::implicit_euler, Integrator::local_global};

// A 4 x 4 x 4 box standing on its anchored bottom face.
Lattice standing_box(const Material& m) {
  Lattice l = make_box(4, 4, 4, 0.01, m);
  anchor_where(l, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  return l;
}

int top_centre(const Lattice& l) {
  int best = 0;
  for (int i = 0; i < l.size(); ++i)
    if ((l.rest.col(i) - Eigen::Vector3d(0.015, 0.015, 0.03)).norm() <
        (l.rest.col(best) - Eigen::Vector3d(0.015, 0.015, 0.03)).norm())
      best = i;
  return best;
}

// Largest energy an integrator may show starting from energy e0 without
// any work done on it. Explicit ones conserve a modified energy that
// differs from the true one by a factor within (1 -+ w h / 2) for each
// mode (exact for symplectic Euler on an oscillator). RK4 inside its
// stability region shrinks every mode of the linearised lattice (1% slack
// for the nonlinearity); implicit ones dissipate.
double ceiling(const Simulator& sim, double e0) {
  if (!is_explicit(sim.options().integrator)) return e0 * (1 + 1e-9) + 1e-15;
  if (sim.options().integrator == Integrator::rk4) return e0 * 1.01 + 1e-15;
  const double wh = sim.spectrum().omega_max * sim.options().dt / sim.substeps();
  return e0 * (1 + wh / 2) / (1 - wh / 2) + 1e-15;
}

// Runs `steps` steps; asserts a finite state and energy below `limit` at every step.
void run(Simulator& sim, State& s, int steps, const std::vector<PointForce>& loads, double limit) {
  for (int k = 0; k < steps; ++k) {
    sim.step(s, loads);
    ASSERT_TRUE(s.x.allFinite() && s.v.allFinite()) << "step " << k;
    ASSERT_LT(energy(sim.lattice(), s.x, s.v).total(), limit) << "step " << k;
  }
}

TEST(MassspringHardCases, VeryStiffSpringsSubstepOrRefuseExplicitly) {
  Material m;
  m.k = 1e6;  // omega_max ~ 1e5 rad/s: omega dt ~ 100 at dt = 1 ms
  m.b = 1;
  const Lattice l = standing_box(m);
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    o.on_unstable = OnUnstable::refuse;
    if (is_explicit(in)) {
      try {
        Simulator refused(l, o);
        FAIL() << "a step 100 times the stable one was accepted";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("exceeds the stable step"), std::string::npos) << e.what();
      }
      o.on_unstable = OnUnstable::substep;
    }
    Simulator sim(l, o);
    EXPECT_EQ(sim.substeps() > 1, is_explicit(in));
    State s = rest_state(l);
    s.x.col(top_centre(l)).z() += 0.005;  // a stretch of half a cell
    const double e0 = energy(l, s.x, s.v).total();
    run(sim, s, 50, {}, ceiling(sim, e0));
  }
}

TEST(MassspringHardCases, TooManySubstepsAreRefusedWithTheReason) {
  Material m;
  m.k = 1e9;
  Options o;
  o.integrator = Integrator::rk4;
  o.dt = 1.0 / 30;
  try {
    Simulator sim(standing_box(m), o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_substeps"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("implicit_euler"), std::string::npos) << e.what();
  }
}

TEST(MassspringHardCases, MassRatioTenThousand) {
  Material m;
  m.b = 0.01;
  Lattice l = standing_box(m);
  for (int i = 0; i < l.size(); i += 2) l.mass[i] *= 1e4;
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    Simulator sim(l, o);
    State s = rest_state(l);
    s.v.col(top_centre(l)) << 0.1, 0, -0.2;
    const double e0 = energy(l, s.x, s.v).total();
    run(sim, s, 300, {}, ceiling(sim, e0));
  }
}

// The video rate: implicit integrators take dt = 1/30 s in one step and
// still settle under a load; explicit ones substep.
TEST(MassspringHardCases, VideoRateStep) {
  Material m;
  m.b = 0.05;
  const Lattice l = standing_box(m);
  const std::vector<PointForce> press{{top_centre(l), Eigen::Vector3d(0, 0, -0.5)}};
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1.0 / 30;
    Simulator sim(l, o);
    EXPECT_EQ(sim.substeps() > 1, is_explicit(in));
    State s = rest_state(l);
    run(sim, s, 90, press, 1.0);
    EXPECT_LT(s.x(2, top_centre(l)), 0.03 - 1e-3);  // pressed in
    EXPECT_GT(s.x(2, top_centre(l)), 0.0);          // not through the floor
  }
}

TEST(MassspringHardCases, ZeroLengthAndNearZeroSprings) {
  // Two masses at the same point joined by a zero-length spring, one joined
  // to an anchor by a 1e-15 m spring: directions are undefined at rest.
  Lattice l;
  l.rest.setZero(3, 4);
  l.rest.col(3) << 1e-15, 0, 0;
  l.mass.setConstant(4, 0.01);
  l.anchored = {1, 0, 0, 0};
  l.springs = {{0, 1, 0.0, 10, 0.1}, {1, 2, 0.0, 10, 0.1}, {2, 3, 1e-15, 10, 0.1}};
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    Simulator sim(l, o);
    State s = rest_state(l);
    run(sim, s, 100, {}, 1e-12);  // nothing moves: every spring is at rest
    s.v.col(2) << 0.3, -0.1, 0.2;
    const double e0 = energy(l, s.x, s.v).total();
    run(sim, s, 3000, {}, ceiling(sim, e0));
    EXPECT_LT(energy(l, s.x, s.v).total(), 0.5 * e0);  // the dampers worked
  }
}

// Two vertices at the same place (as from an unwelded mesh), each with its
// own springs, plus a spring between them.
TEST(MassspringHardCases, DuplicateVertices) {
  Material m;
  m.b = 0.02;
  Lattice l = standing_box(m);
  const int top = top_centre(l), twin = l.size();
  l.rest.conservativeResize(3, twin + 1);
  l.rest.col(twin) = l.rest.col(top);
  l.mass.conservativeResize(twin + 1);
  l.mass[twin] = l.mass[top];
  l.anchored.push_back(0);
  l.springs.push_back({top, twin, 0.0, m.k, m.b});
  l.springs.push_back({twin, 0, (l.rest.col(twin) - l.rest.col(0)).norm(), m.k, m.b});
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    Simulator sim(l, o);
    State s = rest_state(l);
    run(sim, s, 300, {{twin, Eigen::Vector3d(0.2, 0, 0)}}, 1.0);
    EXPECT_GT(s.x(0, top), l.rest(0, top));  // the pull reached its twin
  }
}

TEST(MassspringHardCases, CollapsedAndInvertedBox) {
  Material m;
  m.b = 0.05;
  const Lattice l = make_box(4, 4, 4, 0.01, m);
  const Eigen::Vector3d centre(0.015, 0.015, 0.015);
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    Simulator sim(l, o);
    // Collapsed to its centre point: every spring has zero length and
    // falls back to its rest direction, so the box expands back.
    State s = rest_state(l);
    for (int i = 0; i < l.size(); ++i) s.x.col(i) = centre;
    const double e0 = energy(l, s.x, s.v).total();
    run(sim, s, 2000, {}, ceiling(sim, e0));
    EXPECT_LT(energy(l, s.x, s.v).elastic, 0.01 * e0);
    // Inverted (mirrored through its centre): spring lengths are those at
    // rest, so a mass-spring box has no force to undo it and stays put.
    s = rest_state(l);
    for (int i = 0; i < l.size(); ++i) s.x.col(i) = 2 * centre - l.rest.col(i);
    const Eigen::Matrix3Xd inverted = s.x;
    run(sim, s, 100, {}, 1e-12);
    EXPECT_LT((s.x - inverted).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// A spike 100 times the PHANToM Omni's 3.3 N peak for one step, then
// release: the box rings and settles, bounded by the work the spike did.
TEST(MassspringHardCases, ForceSpikeHundredTimesTheDeviceMaximum) {
  Material m;
  m.b = 0.05;
  const Lattice l = standing_box(m);
  const int top = top_centre(l);
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    Simulator sim(l, o);
    State s = rest_state(l);
    sim.step(s, {{top, Eigen::Vector3d(0, 0, -330)}});
    // Impulse 0.33 N s on 1 g: the work is at most (F dt)^2 / 2m = 54 J.
    const double e1 = energy(l, s.x, s.v).total();
    ASSERT_LT(e1, 60);
    run(sim, s, 3000, {}, ceiling(sim, e1));
    EXPECT_LT(energy(l, s.x, s.v).total(), 0.01 * e1);
  }
}

// The contact jumps from one side of the box to the other between steps.
TEST(MassspringHardCases, ContactTeleportsAcrossTheObject) {
  Material m;
  m.b = 0.05;
  const Lattice l = standing_box(m);
  const int a = l.size() - 1, b = l.size() - 16;  // opposite top corners
  for (Integrator in : kAll) {
    SCOPED_TRACE(name(in));
    Options o;
    o.integrator = in;
    o.dt = 1e-3;
    Simulator sim(l, o);
    State s = rest_state(l);
    for (int k = 0; k < 200; ++k) {
      sim.step(s, {{k % 2 ? a : b, Eigen::Vector3d(0, 0, -2.0)}});
      ASSERT_TRUE(s.x.allFinite());
    }
    EXPECT_LT(s.x(2, a), l.rest(2, a));
    EXPECT_LT(s.x(2, b), l.rest(2, b));
    EXPECT_LT(energy(l, s.x, s.v).total(), 1.0);
  }
}

// 10^6 undamped symplectic Euler steps: the energy oscillates within a band
// of relative width w h and does not drift.
TEST(MassspringHardCases, MillionUndampedSymplecticStepsDoNotDrift) {
  Material m;
  Lattice l = make_sheet(4, 3, 0.01, m);  // 2 free masses in a frame
  Options o;
  o.integrator = Integrator::symplectic_euler;
  o.dt = 1e-3;
  Simulator sim(l, o);
  State s = rest_state(l);
  s.v.col(5) << 0.1, 0.05, 0.02;
  const double e0 = energy(l, s.x, s.v).total();
  const int n = 1'000'000;
  double lo_first = e0, hi_first = e0, lo_last = e0, hi_last = e0;
  for (int k = 0; k < n; ++k) {
    sim.step(s, {});
    const double e = energy(l, s.x, s.v).total();
    if (k < n / 10) lo_first = std::min(lo_first, e), hi_first = std::max(hi_first, e);
    if (k >= n - n / 10) lo_last = std::min(lo_last, e), hi_last = std::max(hi_last, e);
  }
  const double w_h = sim.spectrum().omega_max * o.dt;
  EXPECT_LT(hi_last - lo_last, w_h * e0);                                // a bounded band...
  EXPECT_NEAR(lo_last, lo_first, 0.02 * (hi_first - lo_first) + 1e-15);  // ...that stays put
  EXPECT_NEAR(hi_last, hi_first, 0.02 * (hi_first - lo_first) + 1e-15);
}

// Damping from none to 10 times critical on one oscillator: no integrator
// gains energy, and past critical nothing overshoots the rest length.
TEST(MassspringHardCases, DampingFromZeroToOverCritical) {
  for (double zeta : {0.0, 0.1, 1.0, 3.0, 10.0}) {
    for (Integrator in : kAll) {
      SCOPED_TRACE(std::string(name(in)) + " zeta " + std::to_string(zeta));
      Lattice l;
      l.rest.setZero(3, 2);
      l.rest(0, 1) = 1;
      const double w = 50, k = w * w * 0.01;
      l.mass = Eigen::Vector2d(1, 0.01);
      l.anchored = {1, 0};
      l.springs = {{0, 1, 1.0, k, 2 * zeta * w * 0.01}};
      Options o;
      o.integrator = in;
      o.dt = 1e-3;
      Simulator sim(l, o);
      State s = rest_state(l);
      s.x(0, 1) = 1.2;
      const double e0 = energy(l, s.x, s.v).total();
      double min_x = 2;
      for (int step = 0; step < 2000; ++step) {
        sim.step(s, {});
        const double e = energy(l, s.x, s.v).total();
        ASSERT_TRUE(std::isfinite(e));
        ASSERT_LE(e, ceiling(sim, e0)) << "step " << step;
        min_x = std::min(min_x, s.x(0, 1));
      }
      if (zeta >= 1) EXPECT_GE(min_x, 1.0 - 1e-9) << "overshoot past critical damping";
      if (zeta > 0) EXPECT_LT(energy(l, s.x, s.v).total(), 0.01 * e0);
    }
  }
}

}  // namespace
}  // namespace hcosim::models::massspring
