// The AprilTag detector against the synthetic camera's ground truth: corners
// in the tag frame's order to a fifth of a pixel, the edge refit beating
// libapriltag's corners, and bad input refused.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "models/vision/detector.h"
#include "models/vision/pose.h"
#include "models/vision/synthetic.h"
#include "tests/support/tag_views.h"

namespace hcosim::models::vision {
namespace {

using tests::max_corner_error;
using tests::tilted;

// Tilted tags keep a small corner bias after the refit (docs/tracking.md).
TEST(Vision, CornersComeInTheTagFramesOrderToAFifthOfAPixel) {
  const Intrinsics k = synthetic_intrinsics(640, 480);
  const SyntheticCamera cam(k, Marker{});
  for (const double turn : {0.0, 30.0, 100.0, 200.0, 290.0}) {
    const Eigen::Isometry3d pose = tilted(0.3, 20, turn, 0.02);
    const std::vector<Detection> found = Detector(DetectorParams{}).detect(cam.render(pose));
    ASSERT_EQ(found.size(), 1u) << "turn " << turn;
    EXPECT_EQ(found[0].id, 0);
    EXPECT_LT(max_corner_error(found[0], cam.corners(pose)), 0.2) << "turn " << turn;
  }
}

TEST(Vision, EdgeRefitBeatsLibapriltagsCorners) {
  const Intrinsics k = synthetic_intrinsics(640, 480);
  const SyntheticCamera cam(k, Marker{});
  DetectorParams plain;
  plain.refine_corners = false;
  double refined = 0, raw = 0;
  for (const Eigen::Isometry3d& pose : random_poses(k, 0.05, 20, 3)) {
    const cv::Mat frame = cam.render(pose);
    const auto a = Detector(DetectorParams{}).detect(frame), b = Detector(plain).detect(frame);
    ASSERT_EQ(a.size(), 1u);
    ASSERT_EQ(b.size(), 1u);
    refined += max_corner_error(a[0], cam.corners(pose)), raw += max_corner_error(b[0], cam.corners(pose));
  }
  EXPECT_LT(refined, 0.6 * raw);
}

TEST(Vision, BadInputIsRefused) {
  EXPECT_THROW(Family("tag99h1"), std::invalid_argument);
  EXPECT_THROW(Family("tag36h11").image(587), std::invalid_argument);
  const Detector d(DetectorParams{});
  EXPECT_THROW(d.detect(cv::Mat(480, 640, CV_8UC3)), std::invalid_argument);
  DetectorParams bad;
  bad.quad_decimate = 0.5;
  EXPECT_THROW(Detector{bad}, std::invalid_argument);
  Intrinsics k = synthetic_intrinsics(640, 480);
  std::array<Eigen::Vector2d, 4> corners{};
  corners[2].x() = std::nan("");
  EXPECT_THROW(estimate_pose(corners, 0.05, k), std::invalid_argument);
  k.fx = -1;
  EXPECT_THROW(check(k), std::invalid_argument);
  EXPECT_THROW(SyntheticCamera(k, Marker{}), std::invalid_argument);
  EXPECT_TRUE(Detector(DetectorParams{}).detect(cv::Mat(480, 640, CV_8U, cv::Scalar(128))).empty());
}

}  // namespace
}  // namespace hcosim::models::vision
