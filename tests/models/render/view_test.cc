// What the AR view draws lands where the camera says: a rigid cube drawn
// through the view shows its colour at its top's projected centre and leaves
// the background elsewhere; the stylus and its force arrow appear where their
// points project; the synthetic camera's upright orbit keeps the marker's up
// on the image's up.
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "models/render/view.h"
#include "models/vision/synthetic.h"
#include "models/vision/tracker.h"

namespace hcosim::models::render {

using namespace models::vision;

namespace {

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

}  // namespace
}  // namespace hcosim::models::render
