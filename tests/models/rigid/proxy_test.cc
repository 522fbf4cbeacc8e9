// The contact proxy stays on the touched face without popping through, and
// on a sphere's top past its centre; a NaN HIP is refused.
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
  Proxy proxy;
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
  const Eigen::Vector3d f = proxy_force(proxy.update(cube, r, Eigen::Vector3d(0.01, 0.005, 0.015)),
                                        Eigen::Vector3d(0.01, 0.005, 0.015), 500, 3.3);
  EXPECT_NEAR(f.z(), 3.0, 1e-9);  // 6 mm deep at 500 N/m
  EXPECT_NEAR(proxy_force(Eigen::Vector3d(0, 0, 0.021), Eigen::Vector3d(0, 0, -0.01), 500, 3.3).norm(), 3.3, 1e-12);
  proxy.update(cube, r, Eigen::Vector3d(0.01, 0.005, 0.03));
  EXPECT_FALSE(proxy.in_contact());
}

TEST(RigidProxy, SphereProxyStaysOnTopPastTheCentre) {
  const Body ball = body(Shape::sphere);
  Proxy proxy;
  proxy.update(ball, 0, Eigen::Vector3d(0, 0, 0.05));
  for (double z = 0.019; z > -0.015; z -= 0.001) {
    const Eigen::Vector3d p = proxy.update(ball, 0, Eigen::Vector3d(0, 0, z));
    EXPECT_NEAR(p.z(), 0.02, 1e-9) << z;
  }
}

TEST(RigidProxy, RefusesANanHip) {
  Proxy p;
  EXPECT_THROW(p.update(body(Shape::cube), 0, Eigen::Vector3d(0, NAN, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::rigid
