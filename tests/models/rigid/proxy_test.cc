// The contact proxy stays on the touched face without popping through, and
// on a sphere's top past its centre; with friction its force stays inside
// the friction cone; a NaN HIP is refused.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "models/rigid/proxy.h"

namespace hcosim::models::rigid {
namespace {

Body body(Shape shape, double size = 0.02, double mass = 0.1) {
  Body b;
  b.shape = shape, b.size = size, b.mass = mass;
  return b;
}

// The proxy stays on the face first touched while the HIP is pushed past
// the cube's middle, where the nearest face would be the far one.
TEST(RigidProxy, StaysOnTheTouchedFaceWithoutPopThrough) {
  Body cube = body(Shape::cube);
  Proxy proxy({0, 0});
  const double r = 0.001;
  EXPECT_EQ(proxy.update(cube, r, Eigen::Vector3d(0.003, 0, 0.05)), Eigen::Vector3d(0.003, 0, 0.05));
  EXPECT_FALSE(proxy.in_contact());
  for (double z = 0.03; z > -0.015; z -= 0.001) {
    const Eigen::Vector3d p = proxy.update(cube, r, Eigen::Vector3d(0.003, 0, z));
    if (z < 0.021 - 1e-9) {
      ASSERT_TRUE(proxy.in_contact()) << z;
      EXPECT_NEAR(p.z(), 0.021, 1e-9) << z;
      EXPECT_NEAR(p.x(), 0.003, 1e-9) << z;
    }
  }
  // Sliding inside moves the proxy along the face; leaving frees it.
  EXPECT_NEAR(proxy.update(cube, r, Eigen::Vector3d(0.01, 0.005, 0.015)).x(), 0.01, 1e-9);
  const Eigen::Vector3d h(0.01, 0.005, 0.015);
  EXPECT_NEAR((proxy.update(cube, r, h) - h).z(), 0.006, 1e-9);  // 6 mm deep
  proxy.update(cube, r, Eigen::Vector3d(0.01, 0.005, 0.03));
  EXPECT_FALSE(proxy.in_contact());
}

TEST(RigidProxy, SphereProxyStaysOnTopPastTheCentre) {
  const Body ball = body(Shape::sphere);
  Proxy proxy({0, 0});
  proxy.update(ball, 0, Eigen::Vector3d(0, 0, 0.05));
  for (double z = 0.019; z > -0.015; z -= 0.001) {
    const Eigen::Vector3d p = proxy.update(ball, 0, Eigen::Vector3d(0, 0, z));
    EXPECT_NEAR(p.z(), 0.02, 1e-9) << z;
  }
}

// The spring's force (along proxy - HIP): its part along the face over
// its part across it.
double tangential_over_normal(const Eigen::Vector3d& f, const Eigen::Vector3d& n) {
  return (f - f.dot(n) * n).norm() / f.dot(n);
}

// Press a cube's top 3 mm and stroke 20 mm along it at 1 cm/s (1 kHz):
// the felt force stays inside the friction cone, on its dynamic rim while
// slipping; without friction it is along the normal.
TEST(RigidProxy, AStrokeOnACubeFeelsItsFriction) {
  for (const haptic::Friction f : {haptic::Friction{0, 0}, haptic::Friction{0.3, 0.3}, haptic::Friction{0.6, 0.4}}) {
    const Body cube = body(Shape::cube);
    Proxy proxy(f);
    proxy.update(cube, 0, Eigen::Vector3d(0, 0, 0.03));
    for (double z = 0.0199; z > 0.017; z -= 0.0001) proxy.update(cube, 0, Eigen::Vector3d(0, 0, z));
    double most = 0, slipping = 0;
    std::size_t slips = 0;
    for (int k = 1; k <= 2000; ++k) {
      const Eigen::Vector3d h(-0.01 + 1e-5 * k, 0, 0.017);
      const Eigen::Vector3d p = proxy.update(cube, 0, h);
      ASSERT_TRUE(proxy.in_contact());
      EXPECT_NEAR(p.z(), 0.02, 1e-12);  // on the face, never inside
      const double r = tangential_over_normal(p - h, Eigen::Vector3d::UnitZ());
      most = std::max(most, r);
      if (proxy.slipping()) slipping = std::max(slipping, r), ++slips;
    }
    EXPECT_LE(most, f.static_mu + 1e-9) << f.static_mu;
    if (f.static_mu > 0) {
      EXPECT_GT(slips, 1500u);
      EXPECT_NEAR(slipping, f.dynamic_mu, 1e-9);
    }
  }
}

// On a sphere the cone is about the normal where the proxy is.
TEST(RigidProxy, AStrokeOverASphereStaysInsideItsCone) {
  const Body ball = body(Shape::sphere);
  Proxy proxy({0.4, 0.3});
  proxy.update(ball, 0, Eigen::Vector3d(0, 0, 0.03));
  for (double z = 0.0199; z > 0.017; z -= 0.0001) proxy.update(ball, 0, Eigen::Vector3d(0, 0, z));
  double most = 0;
  for (int k = 1; k <= 1500; ++k) {
    const double a = 1e-3 * k;  // rad: over the top and down its side
    const Eigen::Vector3d h = 0.017 * Eigen::Vector3d(std::sin(a), 0, std::cos(a));
    const Eigen::Vector3d p = proxy.update(ball, 0, h);
    EXPECT_NEAR(p.norm(), 0.02, 1e-12);
    most = std::max(most, tangential_over_normal(p - h, p.normalized()));
  }
  EXPECT_LE(most, 0.4 + 0.02);
  EXPECT_GT(most, 0.3 - 0.02);  // friction is felt
}

// A contact that ends leaves no slip behind: the next starts stuck.
TEST(RigidProxy, EachContactStartsStuck) {
  const Body cube = body(Shape::cube);
  Proxy proxy({0.5, 0.1});
  proxy.update(cube, 0, Eigen::Vector3d(0, 0, 0.03));
  proxy.update(cube, 0, Eigen::Vector3d(0, 0, 0.018));
  proxy.update(cube, 0, Eigen::Vector3d(0.005, 0, 0.018));
  ASSERT_TRUE(proxy.slipping());
  proxy.update(cube, 0, Eigen::Vector3d(0.005, 0, 0.03));
  EXPECT_FALSE(proxy.slipping());
  proxy.update(cube, 0, Eigen::Vector3d(0.005, 0, 0.018));
  EXPECT_LT((proxy.update(cube, 0, Eigen::Vector3d(0.0055, 0, 0.018)) - Eigen::Vector3d(0.005, 0, 0.02)).norm(), 1e-12);
}

TEST(RigidProxy, RefusesANanHip) {
  Proxy p({0, 0});
  EXPECT_THROW(p.update(body(Shape::cube), 0, Eigen::Vector3d(0, NAN, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::rigid
