// Body-body contact geometry against cases whose answer is known: spheres,
// a sphere on a cube's face and corner, cubes face on face, corner on face
// and edge across edge, and separated pairs; the normal always points
// from the first body to the second.
#include <cmath>

#include <gtest/gtest.h>

#include "models/rigid/collide.h"

namespace hcosim::models::rigid {
namespace {

Body body(Shape shape, double size, const Eigen::Vector3d& x,
          const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  Body b;
  b.shape = shape, b.size = size, b.x = x, b.q = q;
  return b;
}

void expect_contact(const Body& a, const Body& b, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                    double depth, double tol = 1e-12) {
  Contact c;
  ASSERT_TRUE(collide(a, b, 0, c));
  EXPECT_LT((c.point - point).norm(), tol) << c.point.transpose();
  EXPECT_LT((c.normal - normal).norm(), 1e-12) << c.normal.transpose();
  EXPECT_NEAR(c.depth, depth, 1e-12);
  Contact r;
  ASSERT_TRUE(collide(b, a, 0, r));  // the same contact seen from the other body
  EXPECT_LT((r.normal + normal).norm(), 1e-12);
  EXPECT_NEAR(r.depth, depth, 1e-12);
}

TEST(RigidCollide, SpheresTouchOnTheirCentreLine) {
  const Eigen::Vector3d u = Eigen::Vector3d(1, 2, 2) / 3;
  expect_contact(body(Shape::sphere, 0.01, Eigen::Vector3d::Zero()), body(Shape::sphere, 0.02, 0.029 * u), 0.0095 * u,
                 u, 0.001);
  Contact c;
  EXPECT_FALSE(collide(body(Shape::sphere, 0.01, Eigen::Vector3d::Zero()), body(Shape::sphere, 0.02, 0.031 * u), 0, c));
  EXPECT_TRUE(
      collide(body(Shape::sphere, 0.01, Eigen::Vector3d::Zero()), body(Shape::sphere, 0.02, 0.031 * u), 0.002, c));
  EXPECT_NEAR(c.depth, -0.001, 1e-12);
}

TEST(RigidCollide, ASphereOnACubesFaceAndCorner) {
  const Body cube = body(Shape::cube, 0.02, Eigen::Vector3d::Zero());
  // On the top face, off its centre: straight down.
  expect_contact(cube, body(Shape::sphere, 0.01, Eigen::Vector3d(0.005, -0.01, 0.029)),
                 Eigen::Vector3d(0.005, -0.01, 0.0195), Eigen::Vector3d::UnitZ(), 0.001);
  // On the corner (+, +, +): along the diagonal.
  const Eigen::Vector3d d = Eigen::Vector3d::Ones().normalized();
  const Eigen::Vector3d corner = 0.02 * Eigen::Vector3d::Ones();
  expect_contact(cube, body(Shape::sphere, 0.01, corner + 0.009 * d), corner - 0.0005 * d, d, 0.001);
  // A turned cube: its face's normal.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d n = q * Eigen::Vector3d::UnitX();
  expect_contact(body(Shape::cube, 0.02, Eigen::Vector3d::Zero(), q), body(Shape::sphere, 0.01, 0.029 * n), 0.0195 * n,
                 n, 0.001);
}

TEST(RigidCollide, CubesFaceOnFaceCornerOnFaceAndEdgeAcrossEdge) {
  const Body low = body(Shape::cube, 0.02, Eigen::Vector3d::Zero());
  // A cube lying on another, offset: the centre of the overlap of their
  // faces, along the face normal.
  expect_contact(low, body(Shape::cube, 0.02, Eigen::Vector3d(0.01, 0.004, 0.039)),
                 Eigen::Vector3d(0.005, 0.002, 0.0195), Eigen::Vector3d::UnitZ(), 0.001, 1e-6);
  // A cube balanced on its corner over the other's face: the corner.
  const Eigen::Vector3d diagonal = Eigen::Vector3d::Ones().normalized();
  const Eigen::Quaterniond corner_down = Eigen::Quaterniond::FromTwoVectors(-diagonal, -Eigen::Vector3d::UnitZ());
  const double reach = std::sqrt(3.0) * 0.02;
  expect_contact(low, body(Shape::cube, 0.02, Eigen::Vector3d(0.003, -0.002, 0.02 + reach - 0.001), corner_down),
                 Eigen::Vector3d(0.003, -0.002, 0.0195), Eigen::Vector3d::UnitZ(), 0.001, 1e-5);
  // Two cubes each turned 45 degrees, one about x and one about y, their
  // edges crossing: the crossing, along z.
  const Eigen::Quaterniond about_x(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond about_y(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()));
  const double edge = std::sqrt(2.0) * 0.02;
  Contact c;
  ASSERT_TRUE(collide(body(Shape::cube, 0.02, Eigen::Vector3d::Zero(), about_x),
                      body(Shape::cube, 0.02, Eigen::Vector3d(0, 0, 2 * edge - 0.001), about_y), 0, c));
  EXPECT_LT((c.normal - Eigen::Vector3d::UnitZ()).norm(), 1e-9) << c.normal.transpose();
  EXPECT_NEAR(c.depth, 0.001, 1e-9);
  EXPECT_LT((c.point - Eigen::Vector3d(0, 0, edge - 0.0005)).norm(), 1e-4) << c.point.transpose();
  EXPECT_FALSE(collide(body(Shape::cube, 0.02, Eigen::Vector3d::Zero(), about_x),
                       body(Shape::cube, 0.02, Eigen::Vector3d(0, 0, 2 * edge + 0.001), about_y), 0, c));
  // Apart along a diagonal where their bounding spheres still overlap.
  EXPECT_FALSE(collide(low, body(Shape::cube, 0.02, Eigen::Vector3d(0.041, 0.041, 0)), 0, c));
}

}  // namespace
}  // namespace hcosim::models::rigid
