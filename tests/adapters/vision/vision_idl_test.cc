#include <gtest/gtest.h>

#include "adapters/validate.h"
#include "adapters/vision/vision_idl.h"

namespace hcosim::adapters::vision {

// The vision models this adapter converts.
using namespace models::vision;
namespace {

TEST(VisionIdl, MarkerPoseCarriesTheTagsPoseAndQuality) {
  models::vision::Observation o;
  o.detection.id = 7;
  o.detection.decision_margin = 88.5;
  o.pose.tag_in_camera = Eigen::Translation3d(0.01, -0.02, 0.4) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY());
  o.pose.reprojection_error_px = 0.12;
  const MarkerPose m = marker_pose("cam", "tag36h11", StepStamp(), 42, 0.05, o, 3.5);
  EXPECT_EQ(m.camera().to_string(), "cam");
  EXPECT_EQ(m.tag_id(), 7);
  EXPECT_EQ(m.frame(), 42u);
  EXPECT_DOUBLE_EQ(m.tag_in_camera().position().z(), 0.4);
  EXPECT_NEAR(m.tag_in_camera().orientation().w(), std::cos(0.25), 1e-15);
  EXPECT_NEAR(m.tag_in_camera().orientation().y(), std::sin(0.25), 1e-15);
  EXPECT_DOUBLE_EQ(m.reprojection_error_px(), 0.12);
  EXPECT_DOUBLE_EQ(m.decision_margin(), 88.5);
  EXPECT_DOUBLE_EQ(m.latency_ms(), 3.5);
  EXPECT_FALSE(validate(m));
}

TEST(VisionIdl, CameraFrameCopiesPixelsOfARegionWithoutItsPadding) {
  cv::Mat big(10, 20, CV_8UC3);
  for (int r = 0; r < big.rows; ++r)
    for (int c = 0; c < big.cols; ++c) big.at<cv::Vec3b>(r, c) = cv::Vec3b(std::uint8_t(r), std::uint8_t(c), 9);
  const cv::Mat roi = big(cv::Rect(5, 2, 8, 4));  // rows 60 bytes apart in memory, 24 bytes each
  models::vision::Intrinsics k = synthetic_intrinsics(640, 480);
  k.distortion[0] = -0.1;
  const CameraFrame f = camera_frame("cam", StepStamp(), 3, roi, k);
  EXPECT_EQ(f.encoding().to_string(), "bgr8");
  ASSERT_EQ(f.width(), 8u);
  ASSERT_EQ(f.height(), 4u);
  ASSERT_EQ(f.data().size(), 8u * 4u * 3u);
  EXPECT_EQ(f.data()[0], 2);                  // row 2 of the big image
  EXPECT_EQ(f.data()[1], 5);                  // column 5
  EXPECT_EQ(f.data()[3 * 8 * 3 + 3 * 7], 5);  // last row starts at row 5
  EXPECT_EQ(f.data()[3 * 8 * 3 + 3 * 7 + 1], 12);
  EXPECT_DOUBLE_EQ(f.distortion()[0], -0.1);
  EXPECT_DOUBLE_EQ(f.fx(), 600);
  EXPECT_FALSE(validate(f));
  EXPECT_EQ(camera_frame("cam", StepStamp(), 0, cv::Mat(4, 4, CV_8UC1), k).encoding().to_string(), "mono8");
  EXPECT_THROW(camera_frame("cam", StepStamp(), 0, cv::Mat(4, 4, CV_16UC1), k), std::invalid_argument);
}

TEST(VisionIdl, PixelsAreTheFramesOwnBytes) {
  const Intrinsics k = synthetic_intrinsics(64, 48);
  for (const int type : {CV_8UC3, CV_8UC1}) {
    const CameraFrame f = camera_frame("cam", StepStamp(), 0, cv::Mat(48, 64, type, cv::Scalar::all(7)), k);
    const cv::Mat p = pixels(f);
    EXPECT_EQ(p.type(), type);
    EXPECT_EQ(p.size(), cv::Size(64, 48));
    EXPECT_EQ(p.data, f.data().data());  // no copy
  }
  CameraFrame cut = camera_frame("cam", StepStamp(), 0, cv::Mat(48, 64, CV_8UC3), k);
  cut.data().resize(10);
  EXPECT_THROW(pixels(cut), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::adapters::vision
