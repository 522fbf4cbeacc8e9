// The stylus's virtual coupling to a rigid body: the body receives the
// force felt (per tick, to rounding), a cube pushed along the marker costs
// its friction there and no more, a stroke across a face stays inside the
// stylus's friction cone, the coupling never pulls and never exceeds the
// device's peak, and bad input is refused.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "models/rigid/coupling.h"
#include "models/rigid/world.h"

namespace hcosim::models::rigid {
namespace {

Body body(Shape shape, double size, double mass, const Eigen::Vector3d& x) {
  Body b;
  b.shape = shape, b.size = size, b.mass = mass, b.x = x;
  return b;
}

// One tick as the service runs it: touch, hand the body its load, step.
Touch tick(World& w, Coupling& c, const Eigen::Vector3d& h, const Eigen::Vector3d& hv, double dt) {
  const Touch t = c.touch(w.bodies()[0], 0, h, hv, dt);
  const Wrench l = c.load(w.bodies()[0], dt);
  w.set_load(0, l.force, l.torque);
  w.step(dt);
  return t;
}

// In free space (no gravity, plane, drag), every tick the body's momentum
// changes by minus the force felt times the tick, and its angular momentum
// about the origin by minus the moment of that force at the proxy: the
// force felt is the force applied. The HIP presses a sphere off its
// centre, then strokes across it and lets go.
TEST(RigidCoupling, TheBodyReceivesTheForceFeltEveryTick) {
  for (const Shape shape : {Shape::sphere, Shape::cube}) {
    WorldSpec s;
    s.gravity.setZero(), s.ground = false, s.drag = Drag{0, 0, 0, 0};
    World w(s, {body(shape, 0.012, 0.5, Eigen::Vector3d::Zero())});
    Coupling c(CouplingSpec{}, {0.3, 0.3});
    const double dt = 1e-3;
    int touching = 0;
    for (int k = 0; k < 400; ++k) {
      const Eigen::Vector3d hv(k < 200 ? 0.0 : 0.05, 0, k < 200 ? -0.03 : 0.0);
      const Eigen::Vector3d h = Eigen::Vector3d(0.004, 0.002, 0.016) +
                                1e-3 * Eigen::Vector3d(k < 200 ? 0 : 0.05 * (k - 200), 0, -0.03 * std::min(k, 200));
      const Eigen::Vector3d p0 = momentum(w.bodies()[0]), l0 = angular_momentum(w.bodies()[0]);
      const Touch t = tick(w, c, h, hv, dt);
      touching += t.contact;
      const Eigen::Vector3d dp = momentum(w.bodies()[0]) - p0, dl = angular_momentum(w.bodies()[0]) - l0;
      ASSERT_LT((dp + t.force * dt).norm(), 1e-15) << name(shape) << " tick " << k;
      ASSERT_LT((dl + t.proxy.cross(t.force) * dt).norm(), 1e-16) << name(shape) << " tick " << k;
    }
    EXPECT_GT(touching, 40) << name(shape);
  }
}

// The default scene's box (a 50 g cube of 12 mm half-edge on the marker,
// floor friction 0.5) pushed sideways at 5 cm/s for 2 s: the mean force
// felt over the last second is within 20 % of friction times weight
// and spreads by under 2 % of its mean, and the cube keeps up with the
// hand.
TEST(RigidCoupling, PushingACubeCostsItsFrictionOnThePlane) {
  const WorldSpec s;
  const double m = 0.05, a = 0.012, dt = 1e-3, speed = 0.05;
  World w(s, {body(Shape::cube, a, m, Eigen::Vector3d(0, 0, a))});
  Coupling c(CouplingSpec{}, {0.3, 0.3});
  double sum = 0, squares = 0;
  int n = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d h(-a - 0.002 + speed * dt * k, 0, a);
    const Touch t = tick(w, c, h, Eigen::Vector3d(speed, 0, 0), dt);
    if (k >= 1000) sum += -t.force.x(), squares += t.force.x() * t.force.x(), ++n;
  }
  const double need = s.floor.friction * m * 9.81, mean = sum / n;
  EXPECT_NEAR(mean / need, 1, 0.2) << "mean " << mean << " N against " << need << " N";
  EXPECT_LT(std::sqrt(squares / n - mean * mean), 0.02 * mean);  // steady: the damper holds the spring
  EXPECT_NEAR(w.bodies()[0].v.x(), speed, 0.2 * speed);
  // Slid, not tipped: within 10 um of its height and 1 mrad of upright.
  EXPECT_NEAR(w.bodies()[0].x.z(), a, 1e-5);
  EXPECT_LT(w.bodies()[0].q.angularDistance(Eigen::Quaterniond::Identity()), 1e-3);
}

// A stroke across the top of a heavy cube resting on the marker, pressed
// 3 mm: the felt force leans off the normal by at most the stylus's
// friction + 0.02, and by at least 0.8 of it while sliding; frictionless,
// by nothing.
TEST(RigidCoupling, AStrokeAcrossAFaceFeelsItsFrictionAndNoMore) {
  for (const double mu : {0.0, 0.3, 0.6}) {
    const WorldSpec s;
    const double a = 0.02, dt = 1e-3;
    World w(s, {body(Shape::cube, a, 0.5, Eigen::Vector3d(0, 0, a))});
    Coupling c(CouplingSpec{}, {mu, mu});
    for (int k = 0; k <= 30; ++k)
      tick(w, c, Eigen::Vector3d(-0.01, 0, 2 * a + 0.001 - 1e-4 * k), Eigen::Vector3d::Zero(), dt);
    double most = 0, least = 1e9;
    for (int k = 1; k <= 2000; ++k) {
      const Eigen::Vector3d h(-0.01 + 1e-5 * k, 0, 2 * a - 0.002);
      const Touch t = tick(w, c, h, Eigen::Vector3d(0.01, 0, 0), dt);
      ASSERT_TRUE(t.contact);
      const double r = std::hypot(t.force.x(), t.force.y()) / t.force.z();
      most = std::max(most, r);
      if (k > 200) least = std::min(least, r);
    }
    EXPECT_LE(most, mu + 0.02) << mu;
    EXPECT_GE(least, 0.8 * mu) << mu;
    EXPECT_LT((w.bodies()[0].x - Eigen::Vector3d(0, 0, a)).norm(), 1e-4) << mu;  // the cube held still
  }
}

// A contact starts without a kick: the damper grows from zero with depth,
// so the first tick's force is at most (stiffness + damping x approach
// speed, per mm) times that tick's motion, the spring's alone as the
// approach slows; for a slow press, a push and a 0.5 m/s strike.
TEST(RigidCoupling, AContactStartsWithoutAKick) {
  const CouplingSpec spec;
  for (const double speed : {0.01, 0.1, 0.5})
    for (const double start : {0.0291, 0.02913, 0.02917}) {
      World w(WorldSpec{}, {body(Shape::cube, 0.012, 0.05, Eigen::Vector3d(0, 0, 0.012))});
      Coupling c(spec, {0.3, 0.3});
      const double dt = 1e-3, step = speed * dt;
      for (int k = 0;; ++k) {
        ASSERT_LT(k, 1000);
        const Touch t = tick(w, c, Eigen::Vector3d(0.003, 0, start - step * k), Eigen::Vector3d(0, 0, -speed), dt);
        if (!t.contact) continue;
        EXPECT_LE(t.force.norm(), (spec.stiffness + spec.damping * 1e3 * speed) * step * (1 + 1e-12)) << speed;
        break;
      }
    }
}

// A HIP pulled out of a sphere faster than the sphere recedes is let go
// (the damper never pulls), and no force exceeds the device's peak.
TEST(RigidCoupling, NeverPullsNorExceedsThePeak) {
  const Body b = body(Shape::sphere, 0.02, 0.1, Eigen::Vector3d::Zero());
  Coupling c({500, 50, 3.3}, {0, 0});
  c.touch(b, 0, Eigen::Vector3d(0, 0, 0.03), Eigen::Vector3d::Zero(), 1e-3);
  const Touch deep = c.touch(b, 0, Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d(0, 0, -1), 1e-3);
  EXPECT_NEAR(deep.force.norm(), 3.3, 1e-12);
  EXPECT_TRUE(deep.clamped);
  const Touch out = c.touch(b, 0, Eigen::Vector3d(0, 0, 0.0199), Eigen::Vector3d(0, 0, 1), 1e-3);
  EXPECT_TRUE(out.contact);
  EXPECT_EQ(out.force, Eigen::Vector3d::Zero());  // 0.05 N of spring against 50 N of damper
}

TEST(RigidCoupling, BadInputIsRefused) {
  EXPECT_THROW(Coupling({0, 2, 3.3}, {0, 0}), std::invalid_argument);
  EXPECT_THROW(Coupling({500, -1, 3.3}, {0, 0}), std::invalid_argument);
  EXPECT_THROW(Coupling({500, 2, 0}, {0, 0}), std::invalid_argument);
  EXPECT_THROW(Coupling({500, 2, 3.3}, {0.1, 0.2}), std::invalid_argument);
  Coupling c({500, 2, 3.3}, {0, 0});
  const Body b = body(Shape::cube, 0.02, 0.1, Eigen::Vector3d::Zero());
  EXPECT_THROW(c.touch(b, 0, Eigen::Vector3d(0, NAN, 0), Eigen::Vector3d::Zero(), 1e-3), std::invalid_argument);
  EXPECT_THROW(c.touch(b, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d(INFINITY, 0, 0), 1e-3), std::invalid_argument);
  EXPECT_THROW(c.touch(b, 0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), -1), std::invalid_argument);
  EXPECT_THROW(c.load(b, 0), std::invalid_argument);
  World w(WorldSpec{}, {b});
  EXPECT_THROW(w.set_load(1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(w.set_load(0, Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::Zero()), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::rigid
