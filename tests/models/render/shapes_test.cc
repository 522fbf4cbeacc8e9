// The AR view's shapes are closed and face outward.
#include <gtest/gtest.h>

#include "models/render/shapes.h"

namespace hcosim::models::render {

namespace {

// Every non-degenerate triangle's normal points away from `centre`.
void expect_outward(const Mesh& m, const Eigen::Vector3d& centre) {
  int faces = 0;
  for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
    const Eigen::Vector3d a = m.vertices.col(m.triangles[t]), b = m.vertices.col(m.triangles[t + 1]),
                          c = m.vertices.col(m.triangles[t + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    ++faces;
    EXPECT_GT(n.dot((a + b + c) / 3 - centre), 0) << "triangle " << t / 3;
  }
  EXPECT_GT(faces, 0);
}

TEST(ArShapes, AreClosedAndFaceOutward) {
  const Mesh c = cube(0.01), s = sphere(0.02, 8), y = cylinder(0.003, 0.08, 10);
  EXPECT_EQ(c.vertices.cols(), 24);
  EXPECT_EQ(c.triangles.size(), 36u);
  EXPECT_NEAR(c.vertices.cwiseAbs().maxCoeff(), 0.01, 1e-15);
  expect_outward(c, Eigen::Vector3d::Zero());
  expect_outward(s, Eigen::Vector3d::Zero());
  for (Eigen::Index v = 0; v < s.vertices.cols(); ++v) EXPECT_NEAR(s.vertices.col(v).norm(), 0.02, 1e-15);
  expect_outward(y, Eigen::Vector3d(0, 0, 0.04));
  EXPECT_THROW(cube(0), std::invalid_argument);
  EXPECT_THROW(sphere(0.01, 2), std::invalid_argument);
  EXPECT_THROW(cylinder(0.01, -1), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::render
