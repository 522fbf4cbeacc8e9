// The AR view's topic conversions: meshes, bodies and frames convert, and a
// mesh and a topology that do not belong together are refused.
#include <filesystem>

#include <gtest/gtest.h>

#include "adapters/render/ar_idl.h"
#include "adapters/vision/vision_idl.h"
#include "models/render/view.h"

namespace hcosim::adapters::render {

using namespace models::render;
using namespace models::vision;
namespace {

TEST(ArTopics, MeshesBodiesAndFramesConvert) {
  MeshTopology t;
  t.mesh("cube");
  t.topology_version(1);
  t.vertex_count(3);
  t.triangles({0, 1, 2});
  DeformedMesh m;
  m.mesh("cube");
  m.topology_version(1);
  m.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const Mesh out = mesh(m, t);
  EXPECT_EQ(out.vertices.cols(), 3);
  EXPECT_EQ(out.vertices(0, 1), 1.0);
  m.topology_version(2);
  EXPECT_THROW(mesh(m, t), std::invalid_argument);
  m.topology_version(1);
  m.positions({0, 0, 0});
  EXPECT_THROW(mesh(m, t), std::invalid_argument);

  RigidBodyState b;
  b.body("ball");
  b.shape("sphere");
  b.pose().position().x(0.1);
  b.pose().orientation().w(1);
  const Mesh ball = body(b, 0.02);
  EXPECT_NEAR((ball.vertices.rowwise().mean() - Eigen::Vector3d(0.1, 0, 0)).norm(), 0, 1e-3);
  b.shape("cone");
  EXPECT_THROW(body(b, 0.02), std::invalid_argument);

  // A grey frame comes back as BGR with its intrinsics.
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(64, 48);
  const cv::Mat grey(48, 64, CV_8UC1, cv::Scalar(77));
  const CameraFrame f = adapters::vision::camera_frame("cam", {}, 3, grey, k);
  const cv::Mat bgr = adapters::vision::bgr_image(f);
  EXPECT_EQ(bgr.type(), CV_8UC3);
  EXPECT_EQ(bgr.at<cv::Vec3b>(10, 10), cv::Vec3b(77, 77, 77));
  EXPECT_EQ(adapters::vision::intrinsics(f).fx, k.fx);
  CameraFrame cut = f;
  cut.data().resize(10);
  EXPECT_THROW(adapters::vision::bgr_image(cut), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::adapters::render
