// The rigid model of seed 000 §2.1: eq 2 exactly, conservation per
// collision, restitution's energy loss, spin from an off-centre hit, no
// tunnelling, friction's closed form, resting and sleeping on the marker
// plane, air friction, and bad input refused.
#include <cmath>

#include <gtest/gtest.h>

#include "models/rigid/collide.h"
#include "models/rigid/world.h"

namespace hcosim::models::rigid {
namespace {

WorldSpec free_space(double e, double mu, double tip_radius) {
  WorldSpec s;
  s.gravity.setZero(), s.ground = false, s.drag = Drag{0, 0, 0, 0};
  s.tip = Material{e, mu}, s.tip_radius = tip_radius, s.tip_mass = 0.1;
  return s;
}

Body body_of(Shape shape, double size = 0.02, double mass = 0.1) {
  Body b;
  b.shape = shape, b.size = size, b.mass = mass;
  return b;
}

// 000 eq 2: equal masses and radii, e = 1, over b in [0, 2r].
TEST(Rigid, Eq2IsExactOverEveryImpactParameter) {
  const double r = 0.02;
  for (int k = 0; k <= 40; ++k) {
    const double b = 2 * r * k / 40, s = b / (2 * r), c = std::sqrt(1 - s * s);
    World w(free_space(1, 0, r), {body_of(Shape::sphere, r)});
    w.set_tip({Eigen::Vector3d(-0.1, b, 0), Eigen::Vector3d(1, 0, 0)});
    for (int n = 0; n < 200; ++n) w.step(1e-3);
    SCOPED_TRACE("b/2r = " + std::to_string(s));
    EXPECT_LT((w.bodies()[0].v - c * Eigen::Vector3d(c, -s, 0)).norm(), 1e-9);
    EXPECT_LT((w.tip().v - s * Eigen::Vector3d(s, c, 0)).norm(), 1e-9);
  }
}

// Momentum and angular momentum about the origin, to 1e-12 per collision,
// for hits on a cube and a sphere with friction (the tip a particle, as
// in the seed, so that its friction acts at its centre).
class RigidPerShape : public ::testing::TestWithParam<Shape> {};

TEST_P(RigidPerShape, CollisionsConserveMomentumAndAngularMomentum) {
  const Shape shape = GetParam();
  for (const double mu : {0.0, 0.5})
    for (const double y : {0.0, 0.007, 0.015}) {
      World w(free_space(0.6, mu, 0), {body_of(shape)});
      w.set_tip({Eigen::Vector3d(-0.05, y, 0.004), Eigen::Vector3d(2, 0.1, -0.2)});
      const Eigen::Vector3d p0 = w.momentum(), l0 = w.angular_momentum();
      int hits = 0;
      for (int n = 0; n < 60; ++n) hits += w.step(1e-3).hits;
      SCOPED_TRACE("mu " + std::to_string(mu) + " y " + std::to_string(y));
      EXPECT_EQ(hits, 1);
      EXPECT_LT((w.momentum() - p0).norm(), 1e-12 * p0.norm());
      EXPECT_LT((w.angular_momentum() - l0).norm(), 1e-12 * (l0.norm() + 0.1 * 2 * 0.05));
    }
}

// Without friction a hit keeps (1 - e^2) of nothing: it loses exactly
// (1 - e^2) of the kinetic energy of the approach along the normal,
// 1/2 vn^2 / (n.K.n), and none for e = 1.
TEST(Rigid, EnergyIsLostAsRestitutionSays) {
  for (const double e : {1.0, 0.7, 0.3, 0.0}) {
    const Body b = body_of(Shape::cube);
    const Eigen::Vector3d p(-0.02, 0.008, 0.005), n(-1, 0, 0), tip_v(1.5, 0.2, 0);
    const Eigen::Vector3d P = contact_impulse(b, 0.1, tip_v, p, n, Material{e, 0});
    const Eigen::Vector3d r = p - b.x;
    const double knn = 1 / 0.1 + 1 / b.mass + r.cross(n).squaredNorm() / inertia(b);
    const double vn = tip_v.dot(n);
    Body after = b;
    after.v -= P / b.mass, after.w -= r.cross(P) / inertia(b);
    const double before_e = 0.5 * 0.1 * tip_v.squaredNorm();
    const double after_e = 0.5 * 0.1 * (tip_v + P / 0.1).squaredNorm() + kinetic_energy(after);
    EXPECT_NEAR(before_e - after_e, (1 - e * e) * 0.5 * vn * vn / knn, 1e-12) << "e " << e;
  }
}

// 000 eq 4-7, corrected: a particle hitting a cube's face at lever arm d
// from its centre, e = 1, no friction. The closed form: with
// 1/m* = 1/m1 + 1/m2 + d^2/I, the impulse is j = 2 m* v1; the cube spins at
// j d / I about r x F (eq 7's torque direction).
TEST(Rigid, OffCentreHitSpinsTheCubeAsTheClosedFormSays) {
  const double d = 0.012, v1 = 1.2;
  World w(free_space(1, 0, 0), {body_of(Shape::cube)});
  w.set_tip({Eigen::Vector3d(-0.05, d, 0), Eigen::Vector3d(v1, 0, 0)});
  for (int n = 0; n < 60; ++n) w.step(1e-3);
  const Body& c = w.bodies()[0];
  const double I = inertia(c), m_star = 1 / (1 / 0.1 + 1 / c.mass + d * d / I), j = 2 * m_star * v1;
  EXPECT_NEAR(c.v.x(), j / c.mass, 1e-12);
  // Force +x at r = (-h, d, 0): r x F points along -z.
  EXPECT_LT((c.w - Eigen::Vector3d(0, 0, -j * d / I)).norm(), 1e-10);
  EXPECT_NEAR(w.tip().v.x(), v1 - j / 0.1, 1e-12);
  EXPECT_NEAR(w.kinetic_energy(), 0.5 * 0.1 * v1 * v1, 1e-12);
}

// A tip at rest against a body, and a grazing tip, change nothing.
TEST(Rigid, ZeroVelocityAndGrazingTouchesExchangeNothing) {
  World still(free_space(1, 0.5, 0.002), {body_of(Shape::sphere)});
  still.set_tip({Eigen::Vector3d(-0.022, 0, 0), Eigen::Vector3d::Zero()});
  for (int n = 0; n < 10; ++n) EXPECT_EQ(still.step(1e-3).hits, 0);
  EXPECT_TRUE(still.bodies()[0].v.isZero());
  World graze(free_space(1, 0, 0.002), {body_of(Shape::sphere)});
  graze.set_tip({Eigen::Vector3d(-0.05, 0.022, 0), Eigen::Vector3d(1, 0, 0)});
  for (int n = 0; n < 100; ++n) graze.step(1e-3);
  EXPECT_TRUE(graze.bodies()[0].v.isZero());
  EXPECT_EQ(graze.tip().v, Eigen::Vector3d(1, 0, 0));
}

// 10 m/s at 1 kHz moves the tip 1 cm a step; the 7 mm-wide sphere lies
// between two of its positions and is still hit (and so is a cube).
TEST_P(RigidPerShape, FastStylusDoesNotTunnel) {
  const Shape shape = GetParam();
  World w(free_space(1, 0, 0.0005), {body_of(shape, 0.003, 0.01)});
  w.set_tip({Eigen::Vector3d(-0.0045, 0.0002, 0), Eigen::Vector3d(10, 0, 0)});
  int hits = 0;
  for (int n = 0; n < 3; ++n) hits += w.step(1e-3).hits;
  EXPECT_EQ(hits, 1);
  EXPECT_GT(w.bodies()[0].v.x(), 5);
}

INSTANTIATE_TEST_SUITE_P(, RigidPerShape, ::testing::Values(Shape::cube, Shape::sphere),
                         [](const ::testing::TestParamInfo<Shape>& i) { return std::string(name(i.param)); });

// A spinning sphere hit with friction: the tip is thrown sideways, the
// spin changes about r x F, and momentum is conserved.
TEST(Rigid, SpinningSphereThrowsTheTipSideways) {
  Body ball = body_of(Shape::sphere);
  ball.w = Eigen::Vector3d(0, 0, 40);  // its -x side moves toward -y
  World w(free_space(0.5, 0.4, 0), {ball});
  w.set_tip({Eigen::Vector3d(-0.05, 0, 0), Eigen::Vector3d(1, 0, 0)});
  const Eigen::Vector3d p0 = w.momentum(), l0 = w.angular_momentum();
  for (int n = 0; n < 60; ++n) w.step(1e-3);
  EXPECT_LT(w.tip().v.y(), -0.05);
  EXPECT_LT(w.bodies()[0].w.z(), 40);
  EXPECT_LT((w.momentum() - p0).norm(), 1e-12);
  EXPECT_LT((w.angular_momentum() - l0).norm(), 1e-12);
}

// Where normal and tangential motion decouple (a sphere, a cube's face
// centre) the frictional impulse is in closed form; moving the contact a
// micrometre off the centre line sends it through the 400-increment
// integration instead, which must agree to its resolution: sliding
// throughout (mu P_n), and the slip stopping (stick) part-way.
TEST(Rigid, FrictionClosedFormAgreesWithTheIntegratedImpulse) {
  Body ball = body_of(Shape::sphere);
  ball.w = Eigen::Vector3d(0, 0, 30);
  const Eigen::Vector3d n(-1, 0, 0), p = ball.x + ball.size * n, off(0, 1e-6, 0);
  for (double mu : {0.05, 0.3, 2.0}) {
    for (const Eigen::Vector3d& v : {Eigen::Vector3d(1, 0.3, 0.1), Eigen::Vector3d(1, 0, 0)}) {
      const Material m{0.6, mu};
      const Eigen::Vector3d closed = contact_impulse(ball, 0.1, v, p, n, m);
      const Eigen::Vector3d integrated = contact_impulse(ball, 0.1, v, p + off, n, m);
      EXPECT_LT((closed - integrated).norm(), 5e-3 * closed.norm()) << "mu " << mu << " v " << v.transpose();
    }
  }
  // Sliding throughout: the tangential impulse is mu times the normal one.
  const Material slick{0.6, 0.05};
  const Eigen::Vector3d P = contact_impulse(ball, 0.1, Eigen::Vector3d(1, 0.3, 0.1), p, n, slick);
  EXPECT_NEAR((P - P.dot(n) * n).norm(), 0.05 * std::abs(P.dot(n)), 1e-15);
  // Sticking: the slip at the contact point ends exactly at zero.
  const Material grippy{0.6, 2.0};
  const Eigen::Vector3d v(1, 0.3, 0.1), Q = contact_impulse(ball, 0.1, v, p, n, grippy);
  Body after = ball;
  after.v -= Q / ball.mass;
  after.w -= (p - ball.x).cross(Q) / inertia(ball);
  const Eigen::Vector3d rel = v + Q / 0.1 - point_velocity(after, p);
  EXPECT_LT((rel - rel.dot(n) * n).norm(), 1e-14);
}

// A cube set on the marker plane stays put and falls asleep; a tilted cube
// dropped on it comes to rest flat on a face; asleep, it costs nothing
// until the tip hits it.
TEST(Rigid, CubesRestOnTheMarkerPlaneAndSleep) {
  Body cube = body_of(Shape::cube);
  cube.x = Eigen::Vector3d(0, 0, 0.02);
  World rest(WorldSpec{}, {cube});
  rest.set_tip({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()});
  for (int n = 0; n < 2000; ++n) rest.step(1e-3);
  EXPECT_NEAR(rest.bodies()[0].x.z(), 0.02, 1e-9);
  EXPECT_LT(rest.bodies()[0].q.angularDistance(Eigen::Quaterniond::Identity()), 1e-9);
  EXPECT_TRUE(rest.bodies()[0].sleeping);
  EXPECT_EQ(rest.step(1e-3).simulated, 0);
  rest.set_tip({Eigen::Vector3d(-0.04, 0, 0.02), Eigen::Vector3d(1, 0, 0)});
  for (int n = 0; n < 30; ++n) rest.step(1e-3);
  EXPECT_FALSE(rest.bodies()[0].sleeping);
  EXPECT_GT(rest.bodies()[0].v.x(), 0.1);

  cube.x = Eigen::Vector3d(0, 0, 0.08);
  cube.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 1, 0).normalized()));
  World drop(WorldSpec{}, {cube});
  drop.set_tip({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()});
  int n = 0;
  for (; n < 20000 && !drop.bodies()[0].sleeping; ++n) drop.step(1e-3);
  EXPECT_TRUE(drop.bodies()[0].sleeping) << "after " << n << " steps";
  EXPECT_NEAR(drop.bodies()[0].x.z(), 0.02, 1e-4);
  const Eigen::Vector3d up = drop.bodies()[0].q.conjugate() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(up.cwiseAbs().maxCoeff(), 1, 1e-3);  // a face down
}

// Air friction alone slows a sliding body monotonically until it sleeps.
TEST(Rigid, AirFrictionStopsMotion) {
  WorldSpec s;
  s.gravity.setZero(), s.ground = false;
  Body ball = body_of(Shape::sphere);
  ball.v = Eigen::Vector3d(1, 0.5, 0), ball.w = Eigen::Vector3d(0, 0, 20);
  World w(s, {ball});
  w.set_tip({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()});
  double last = 2;
  int n = 0;
  for (; n < 60000 && !w.bodies()[0].sleeping; ++n) {
    w.step(1e-3);
    ASSERT_LE(w.bodies()[0].v.norm(), last);
    last = w.bodies()[0].v.norm();
  }
  EXPECT_TRUE(w.bodies()[0].sleeping) << "after " << n << " steps";
}

// Body 1 thrown at body 0 at rest in free space, off its centre line:
// every hit keeps linear momentum to rounding, with and without friction;
// an elastic frictionless one keeps kinetic energy to rounding too; the
// bodies end apart.
TEST(RigidPairs, HitsConserveMomentumAndElasticOnesEnergy) {
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()));
  for (const auto& [target, mover] : {std::pair{Shape::sphere, Shape::sphere}, std::pair{Shape::cube, Shape::sphere},
                                      std::pair{Shape::sphere, Shape::cube}, std::pair{Shape::cube, Shape::cube}})
    for (const double y : {0.0, 0.006, 0.014})
      for (const Material m : {Material{1, 0}, Material{0.5, 0}, Material{0.5, 0.5}}) {
        WorldSpec s = free_space(1, 0, 0);
        s.pair = m;
        Body moving = body_of(mover, 0.02, 0.05);
        moving.x = Eigen::Vector3d(-0.06, y, 0.003), moving.v = Eigen::Vector3d(1, 0.1, 0), moving.q = turned;
        World w(s, {body_of(target), moving});
        w.set_tip({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()});
        const Eigen::Vector3d p0 = w.momentum();
        const double e0 = w.kinetic_energy();
        int touches = 0;
        for (int n = 0; n < 100; ++n) touches += w.step(1e-3).touches;
        SCOPED_TRACE(std::string(name(target)) + " hit by " + name(mover) + ", y " + std::to_string(y) + ", e " +
                     std::to_string(m.restitution) + ", mu " + std::to_string(m.friction));
        EXPECT_GE(touches, 1);
        EXPECT_LT((w.momentum() - p0).norm(), 1e-12 * p0.norm());
        if (m.restitution == 1 && m.friction == 0) {
          EXPECT_NEAR(w.kinetic_energy(), e0, 1e-12 * e0);
        }
        if (m.restitution < 1 || m.friction > 0) {
          EXPECT_LT(w.kinetic_energy(), e0);
        }
        Contact c;
        EXPECT_FALSE(collide(w.bodies()[0], w.bodies()[1], 0, c));
      }
}

// 000 eq 2 between two bodies: equal spheres, elastic, head on, swap
// their velocities.
TEST(RigidPairs, EqualSpheresHeadOnSwapVelocities) {
  WorldSpec s = free_space(1, 0, 0);
  s.pair = Material{1, 0};
  Body a = body_of(Shape::sphere), b = body_of(Shape::sphere);
  b.x = Eigen::Vector3d(-0.1, 0, 0), b.v = Eigen::Vector3d(1, 0, 0);
  World w(s, {a, b});
  w.set_tip({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()});
  for (int n = 0; n < 100; ++n) w.step(1e-3);
  EXPECT_LT((w.bodies()[0].v - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LT(w.bodies()[1].v.norm(), 1e-12);
}

// A sphere dropped on a cube resting on the marker comes to rest on its
// top; a cube dropped on a resting sphere falls off it onto the plane; a
// cube dropped on a cube comes to rest on it. No two bodies ever overlap by more
// than one step's travel at the speed of impact, and all end asleep.
TEST(RigidPairs, DroppedBodiesComeToRestOnEachOther) {
  const double a = 0.012;
  struct Case {
    Shape low, high;
    double x;  // m, the dropped body's offset from the low one's axis
  };
  for (const Case& k : {Case{Shape::cube, Shape::sphere, 0.002}, Case{Shape::sphere, Shape::cube, 0.004},
                        Case{Shape::cube, Shape::cube, 0.003}}) {
    Body low = body_of(k.low, a, 0.05), high = body_of(k.high, a, 0.05);
    low.x = Eigen::Vector3d(0, 0, a), high.x = Eigen::Vector3d(k.x, 0, 3 * a + 0.01);
    World w(WorldSpec{}, {low, high});
    w.set_tip({Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()});
    double worst = 0;
    int n = 0;
    for (; n < 20000 && !(w.bodies()[0].sleeping && w.bodies()[1].sleeping); ++n) {
      w.step(1e-3);
      Contact c;
      if (collide(w.bodies()[0], w.bodies()[1], 0, c)) worst = std::max(worst, c.depth);
    }
    SCOPED_TRACE(std::string(name(k.high)) + " on " + name(k.low));
    EXPECT_TRUE(w.bodies()[0].sleeping && w.bodies()[1].sleeping) << "after " << n << " steps";
    EXPECT_LT(worst, 5e-4);  // one step's travel at the 0.44 m/s of impact
    const Body& top = w.bodies()[1];
    if (k.low == Shape::sphere) {
      EXPECT_NEAR(top.x.z(), a, 1e-4);  // on the plane, beside the sphere
    } else {
      EXPECT_NEAR(top.x.z(), 3 * a, 1e-4);  // on the cube
      EXPECT_NEAR(w.bodies()[0].x.z(), a, 1e-6);
    }
  }
}

TEST(Rigid, BadInputIsRefused) {
  Body bad = body_of(Shape::cube);
  bad.mass = -1;
  EXPECT_THROW(World(WorldSpec{}, {bad}), std::invalid_argument);
  WorldSpec s;
  s.tip.restitution = 1.5;
  EXPECT_THROW(World(s, {body_of(Shape::cube)}), std::invalid_argument);
  s = WorldSpec{};
  s.pair.friction = -1;
  EXPECT_THROW(World(s, {body_of(Shape::cube)}), std::invalid_argument);
  World w(WorldSpec{}, {body_of(Shape::cube)});
  EXPECT_THROW(w.set_tip({Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::Zero()}), std::invalid_argument);
  EXPECT_THROW(w.step(0), std::invalid_argument);
  EXPECT_THROW(parse_shape("torus"), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::rigid
