// What the AR view draws lands where the camera says: shapes are closed
// and face outward; a rigid cube drawn through the view shows its colour
// at its top's projected centre and leaves the background elsewhere; the
// stylus and its force arrow appear where their points project; the
// synthetic camera's upright orbit keeps the marker's up on the image's up;
// registration error is measured in pixels and stays under 3 px along the
// default deployment's orbit; time plots are written; and the topic
// conversions refuse a mesh and a topology that do not belong together.
#include <gtest/gtest.h>

#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "adapters/render/ar_idl.h"
#include "adapters/vision/source.h"
#include "adapters/vision/vision_idl.h"
#include "models/render/plot.h"
#include "models/render/view.h"
#include "models/vision/synthetic.h"
#include "models/vision/tracker.h"

namespace hcosim::adapters::render {

// The render and vision models this adapter converts.
using namespace models::render;
using namespace models::vision;
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

cv::Vec3b at(const cv::Mat& img, const Eigen::Vector2d& p) {
  return img.at<cv::Vec3b>(int(std::lround(p.y())), int(std::lround(p.x())));
}

TEST(ArView, ObjectStylusAndForceLandWhereTheyProject) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  models::vision::Orbit o;
  o.upright = true, o.distance = 0.3, o.base_tilt_deg = 40, o.tilt_deg = 0, o.swing = 0;
  const Eigen::Isometry3d pose = models::vision::orbit(0, o);
  const cv::Scalar grey(90, 90, 90);
  cv::Mat img(480, 640, CV_8UC3, grey);
  Canvas canvas(img, k, pose);
  View v;
  Eigen::Isometry3d at_box = Eigen::Isometry3d::Identity();
  at_box.translation() = Eigen::Vector3d(-0.04, 0, 0.01);
  v.objects.push_back({"box", placed(cube(0.01), at_box), cv::Scalar(200, 0, 0)});
  Stylus s;
  s.tip = Eigen::Vector3d(0.04, 0, 0.01);
  s.force = Eigen::Vector3d(2, 0, 0);  // N: a 4 cm arrow at 0.02 m/N
  v.stylus = s;
  draw(v, canvas);
  // The cube's top face centre: blue, shaded (never brighter than the colour).
  const cv::Vec3b top = at(img, canvas.project({-0.04, 0, 0.02}));
  EXPECT_GT(top[0], 80);
  EXPECT_EQ(top[1], 0);
  EXPECT_EQ(top[2], 0);
  // Beside it, the frame is untouched.
  EXPECT_EQ(at(img, canvas.project({-0.04, 0.05, 0})), cv::Vec3b(90, 90, 90));
  // The pen above the tip, the arrow's middle beyond the pen's reach.
  const cv::Vec3b pen = at(img, canvas.project({0.04, 0, 0.05}));
  EXPECT_EQ(pen[0], pen[2]);  // grey
  EXPECT_NE(pen, cv::Vec3b(90, 90, 90));
  const cv::Vec3b arrow = at(img, canvas.project({0.07, 0, 0.01}));
  EXPECT_GT(arrow[2], 150);
  EXPECT_LT(arrow[0], 100);
  // With no force, no arrow.
  cv::Mat plain(480, 640, CV_8UC3, grey);
  Canvas c2(plain, k, pose);
  v.stylus->force = Eigen::Vector3d(0.001, 0, 0);
  draw(v, c2);
  EXPECT_EQ(at(plain, c2.project({0.07, 0, 0.01})), cv::Vec3b(90, 90, 90));
}

TEST(ArView, UprightOrbitKeepsTheMarkersUpOnTheImagesUp) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  models::vision::Orbit o;
  o.upright = true, o.distance = 0.3, o.swing = 0.02, o.base_tilt_deg = 40, o.tilt_deg = 10, o.sweep_deg = 25;
  o.period = 40;
  for (double t : {0.0, 5.0, 10.0, 20.0}) {
    const Eigen::Isometry3d p = models::vision::orbit(t, o);
    const Eigen::Vector2d origin = models::vision::project(k, p, {0, 0, 0});
    // Aimed at the marker's centre, at the orbit's distance.
    EXPECT_NEAR(origin.x(), k.cx, 1e-6);
    EXPECT_NEAR(origin.y(), k.cy, 1e-6);
    EXPECT_NEAR(p.translation().norm(), 0.3 + 0.02 * std::sin(2 * M_PI * t / 40), 1e-12);
    EXPECT_LT(models::vision::project(k, p, {0, 0, 0.05}).y(), origin.y() - 50) << t;  // up is up
    EXPECT_GT(models::vision::project(k, p, {0, -0.05, 0}).y(),
              models::vision::project(k, p, {0, 0.05, 0}).y());  // -y is near
  }
  o.sweep_deg = 180;
  EXPECT_THROW(models::vision::check(o), std::invalid_argument);
}

TEST(ArRegistration, ErrorIsInPixelsAndSmallAlongTheDefaultOrbit) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  const Eigen::Isometry3d truth = models::vision::facing(0.3);
  Eigen::Isometry3d moved = truth;
  moved.translation().x() += 0.001;  // 1 mm at 0.3 m, f = 600 px: 2 px
  const std::vector<Eigen::Vector3d> points{{0, 0, 0}, {0.05, 0.05, 0}};
  EXPECT_EQ(models::vision::registration_error_px(k, truth, truth, points), 0);
  EXPECT_NEAR(models::vision::registration_error_px(k, moved, truth, points), 2, 1e-9);

  // The default deployment's camera and marker (deploy/default.yaml): the
  // sheet's corners and half its edge above them, 40 frames over 20 s.
  models::vision::Marker m;
  m.tag_size = 0.03, m.sheet = 8;
  models::vision::Orbit o;
  o.upright = true, o.distance = 0.3, o.swing = 0.02, o.base_tilt_deg = 40, o.tilt_deg = 10, o.sweep_deg = 25;
  o.period = 40;
  adapters::vision::SyntheticSource source(models::vision::SyntheticCamera(k, m), {}, 2, 40, o);
  models::vision::TrackerParams tp;
  tp.tag_size = m.tag_size;
  models::vision::Tracker tracker(tp, k);
  const double h = 0.5 * m.sheet * m.tag_size;
  std::vector<Eigen::Vector3d> scene;
  for (double z : {0.0, h})
    for (double x : {-h, h})
      for (double y : {-h, h}) scene.emplace_back(x, y, z);
  std::vector<double> errors;
  adapters::vision::Frame f;
  while (source.next(f)) {
    const auto seen = tracker.track(f.image);
    ASSERT_EQ(seen.size(), 1u) << "frame " << f.index;
    errors.push_back(
        models::vision::registration_error_px(k, seen[0].pose.tag_in_camera, source.truth(f.index), scene));
  }
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[std::size_t(0.95 * double(errors.size() - 1))], 3.0);
  EXPECT_LT(errors[errors.size() / 2], 1.0);
}

TEST(ArPlot, DrawsStackedTimePanels) {
  Series a{"cube", {0, 1, 2, 3}, {0, 0.5, 1.0, 0.2}}, b{"organ", {0, 1, NAN, 3}, {0, 2, 1, 0}};
  const cv::Mat img = plot_series("forces", "simulated time (s)", {{"force (N)", {a, b}}, {"penetration (mm)", {a}}});
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1000);
  EXPECT_GT(img.rows, 500);
  // The first series' colour (BGR 180, 119, 31) is drawn.
  cv::Mat mask;
  cv::inRange(img, cv::Scalar(170, 110, 20), cv::Scalar(190, 130, 45), mask);
  EXPECT_GT(cv::countNonZero(mask), 100);
  EXPECT_THROW(plot_series("none", "x", {}), std::invalid_argument);
}

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
