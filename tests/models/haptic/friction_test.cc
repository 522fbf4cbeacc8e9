// The friction cone against the analytic case: a flat surface z = 0 under
// a spring coupling, where the force's tangential-to-normal ratio is the
// HIP's tangential offset over its depth.
#include "models/haptic/friction.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::models::haptic {
namespace {

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitZ();
constexpr double kStiffness = 500;  // N/m

// The spring's force on the hand, and its tangential over normal part.
Eigen::Vector3d force(const Eigen::Vector3d& proxy, const Eigen::Vector3d& h) { return kStiffness * (proxy - h); }
double ratio(const Eigen::Vector3d& f) { return f.head<2>().norm() / f.z(); }

TEST(FrictionCone, WithoutFrictionTheProxyIsTheProjectionAndTheForceIsNormal) {
  FrictionCone cone({0, 0});
  Eigen::Vector3d proxy(0, 0, 0);
  for (int k = 0; k < 100; ++k) {
    const Eigen::Vector3d h(1e-4 * k, -5e-5 * k, -0.002);
    proxy = cone.slide(proxy, kUp, h);
    EXPECT_EQ(proxy, Eigen::Vector3d(h.x(), h.y(), 0));
    EXPECT_EQ(ratio(force(proxy, h)), 0);
  }
}

TEST(FrictionCone, StaticFrictionHoldsUntilTheConesRim) {
  FrictionCone cone({0.5, 0.3});
  const Eigen::Vector3d start(0, 0, 0);
  // 2 mm deep: the static cone allows 1 mm of tangential offset.
  Eigen::Vector3d proxy = cone.slide(start, kUp, {0, 0, -0.002});
  for (double x : {0.0002, 0.0005, 0.00099}) {
    proxy = cone.slide(proxy, kUp, {x, 0, -0.002});
    EXPECT_EQ(proxy, start) << x;
    EXPECT_FALSE(cone.slipping());
    EXPECT_NEAR(ratio(force(proxy, {x, 0, -0.002})), x / 0.002, 1e-12);
  }
  proxy = cone.slide(proxy, kUp, {0.0011, 0, -0.002});
  EXPECT_TRUE(cone.slipping());
  EXPECT_NEAR(ratio(force(proxy, {0.0011, 0, -0.002})), 0.3, 1e-12);
}

// A stroke: press 3 mm, slide 20 mm sideways at 1 cm/s in 1 kHz ticks, stop.
TEST(FrictionCone, ASlidingStrokeFeelsTheDynamicCoefficientAndNeverMore) {
  const Friction f{0.5, 0.3};
  FrictionCone cone(f);
  Eigen::Vector3d proxy(0, 0, 0), h(0, 0, -0.003);
  proxy = cone.slide(proxy, kUp, h);
  double most = 0, sliding_min = 1, sliding_max = 0;
  for (int k = 1; k <= 2000; ++k) {
    h.x() = 1e-5 * k;
    proxy = cone.slide(proxy, kUp, h);
    const double r = ratio(force(proxy, h));
    most = std::max(most, r);
    EXPECT_EQ(proxy.z(), 0);  // on the surface, never inside
    if (cone.slipping()) sliding_min = std::min(sliding_min, r), sliding_max = std::max(sliding_max, r);
  }
  EXPECT_LE(most, f.static_mu + 1e-12);
  EXPECT_NEAR(sliding_min, f.dynamic_mu, 1e-9);
  EXPECT_NEAR(sliding_max, f.dynamic_mu, 1e-9);
  // Stopped: the proxy sticks where it trails, and the felt drag stays.
  const Eigen::Vector3d at_stop = proxy;
  for (int k = 0; k < 100; ++k) proxy = cone.slide(proxy, kUp, h);
  EXPECT_EQ(proxy, at_stop);
  EXPECT_FALSE(cone.slipping());
}

// Energy is not created: over a closed stroke (out and back, pressed, then
// lifted) the hand does non-negative work against the rendered force, and
// friction is what takes it.
TEST(FrictionCone, AClosedStrokeDissipatesAndFrictionlessReturnsIt) {
  for (const Friction f : {Friction{0, 0}, Friction{0.3, 0.3}, Friction{0.8, 0.4}}) {
    FrictionCone cone(f);
    Eigen::Vector3d proxy(0, 0, 0.001), h(0, 0, 0.001);
    double work = 0;  // J, by the hand against the force (trapezoids: exact for the spring)
    const auto move_to = [&](const Eigen::Vector3d& to, int ticks) {
      const Eigen::Vector3d from = h;
      for (int k = 1; k <= ticks; ++k) {
        const Eigen::Vector3d next = from + (to - from) * (double(k) / ticks);
        const Eigen::Vector3d before = force(proxy, h);
        // The object's part: free above the plane, entering where the HIP crosses it.
        if (next.z() > 0)
          proxy = next;
        else
          proxy = cone.slide(h.z() > 0 ? Eigen::Vector3d(next.x(), next.y(), 0) : proxy, kUp, next);
        work -= 0.5 * (before + force(proxy, next)).dot(next - h);
        h = next;
      }
    };
    move_to({0, 0, -0.002}, 300);  // ticks of 10 um: one ends on the surface
    move_to({0.01, 0, -0.002}, 1000);
    move_to({0, 0, -0.002}, 1000);
    move_to({0, 0, 0.001}, 300);
    if (f.dynamic_mu == 0)
      EXPECT_NEAR(work, 0, 1e-12) << "frictionless";
    else
      EXPECT_GT(work, 0.9 * 2 * f.dynamic_mu * kStiffness * 0.002 * 0.01) << f.dynamic_mu;
  }
}

// The cone on a force of any law (a deformable object's, not a spring's):
// a force inside the static cone is kept whole; one outside is put on the
// dynamic rim, its normal part kept, and `keep` says how much of the
// tangential offset stays; a force that does not push is passed through.
TEST(FrictionCone, GripKeepsAnyForceInsideItsCone) {
  FrictionCone cone({0.5, 0.3});
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 2) / 3;
  const Eigen::Vector3d t = Eigen::Vector3d(2, -2, 1) / 3;  // unit, tangent
  FrictionCone::Grip g = cone.grip(2.0 * n + 0.9 * t, n);
  EXPECT_EQ(g.keep, 1);
  EXPECT_EQ(g.force, 2.0 * n + 0.9 * t);
  EXPECT_FALSE(cone.slipping());
  g = cone.grip(2.0 * n + 1.2 * t, n);
  EXPECT_TRUE(cone.slipping());
  EXPECT_NEAR(g.keep, 0.3 * 2.0 / 1.2, 1e-15);
  EXPECT_NEAR(g.force.dot(n), 2.0, 1e-15);
  EXPECT_NEAR((g.force - g.force.dot(n) * n).norm(), 0.6, 1e-15);
  // Slipping, the dynamic cone holds it again.
  g = cone.grip(2.0 * n + 0.55 * t, n);
  EXPECT_EQ(g.keep, 1);
  EXPECT_FALSE(cone.slipping());
  g = cone.grip(-0.1 * n + 5.0 * t, n);
  EXPECT_EQ(g.force, -0.1 * n + 5.0 * t);
  EXPECT_EQ(g.keep, 1);
  EXPECT_FALSE(cone.slipping());
}

TEST(FrictionCone, LiftingOffEndsTheSlip) {
  FrictionCone cone({0.2, 0.1});
  Eigen::Vector3d proxy = cone.slide({0, 0, 0}, kUp, {0, 0, -0.001});
  proxy = cone.slide(proxy, kUp, {0.005, 0, -0.001});
  EXPECT_TRUE(cone.slipping());
  EXPECT_EQ(cone.slide(proxy, kUp, {0.006, 0, 0.0005}), Eigen::Vector3d(0.006, 0, 0.0005));
  EXPECT_FALSE(cone.slipping());
}

TEST(FrictionCone, RefusesCoefficientsThatMakeNoSense) {
  using tests::message_of;
  EXPECT_EQ(message_of<std::invalid_argument>([] {
              FrictionCone({-0.1, 0});
            }),
            "friction: the static coefficient must be finite and >= 0");
  EXPECT_EQ(message_of<std::invalid_argument>([] {
              FrictionCone({0.3, NAN});
            }),
            "friction: the dynamic coefficient must be finite and >= 0");
  EXPECT_EQ(message_of<std::invalid_argument>([] {
              FrictionCone({0.2, 0.4});
            }),
            "friction: the dynamic coefficient must not exceed the static one");
}

}  // namespace
}  // namespace hcosim::models::haptic
