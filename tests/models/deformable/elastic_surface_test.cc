// Seed 000's elastic surfaces: the sheet pressed at one vertex pushes back
// and recovers; the semi-sphere dents inward and its mesh faces outward.
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "models/deformable/elastic_surface.h"
#include "models/deformable/surface.h"

namespace hcosim::models::deformable {
namespace {

TEST(ElasticSurface, SheetPressedAtOneVertexPushesBackAndRecovers) {  // 000 §2.2
  SurfaceSpec s;
  s.options.dt = 1e-3;
  ElasticSurface sheet(s);
  EXPECT_FALSE(sheet.touch(1e-3, Eigen::Vector3d(0, 0, 0.01), false).in_contact);
  double last = 0;
  Touch t;
  for (int k = 1; k <= 500; ++k) {
    t = sheet.touch(1e-3, Eigen::Vector3d(0.001, 0, -0.01 * std::min(1.0, k / 200.0)), false);
    if (k % 50 == 0 && k <= 200) {
      EXPECT_GT(t.force.z(), last);
      last = t.force.z();
    }
  }
  EXPECT_TRUE(t.in_contact);
  EXPECT_NEAR(t.depth, 0.01, 1e-12);
  EXPECT_EQ(sheet.state().x(2, sheet.contact()), -0.01);
  for (int k = 0; k < 5000; ++k) sheet.touch(1e-3, Eigen::Vector3d(0, 0, 0.05), false);
  EXPECT_EQ(sheet.contact(), -1);
  EXPECT_LT((sheet.state().x - sheet.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_THROW(sheet.touch(2e-3, Eigen::Vector3d::Zero(), false), std::invalid_argument);
}

TEST(ElasticSurface, SemiSphereDentsInwardAndItsMeshFacesOutward) {
  SurfaceSpec s;
  s.shape = Shape::semisphere;
  s.resolution = 8;
  s.size = 0.05;
  ElasticSurface dome(s);
  const Eigen::Matrix3Xd x = dome.surface();
  double flux = 0;
  const Eigen::Matrix3Xd n = vertex_normals(x, dome.triangles());
  for (int i = 0; i < n.cols(); ++i) flux += n.col(i).dot(x.col(i));
  EXPECT_GT(flux, 0);
  Touch t;
  for (int k = 1; k <= 400; ++k)
    t = dome.touch(1e-3, Eigen::Vector3d(0, 0, 0.05 - 0.005 * std::min(1.0, k / 200.0)), false);
  EXPECT_TRUE(t.in_contact);
  EXPECT_GT(t.force.z(), 0);
  EXPECT_TRUE(dome.state().x.allFinite());
}

}  // namespace
}  // namespace hcosim::models::deformable
