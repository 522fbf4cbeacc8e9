// Intrinsics files as OpenCV writes them and as ROS writes them, with
// located errors for bad ones.
#include <filesystem>
#include <fstream>
#include <regex>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "adapters/config.h"
#include "adapters/vision/calibration.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::vision {

using namespace models::vision;
namespace {

namespace fs = std::filesystem;

TEST(Camera, IntrinsicsReadBackWhatOpenCvWrites) {
  tests::TempDir dir;
  Intrinsics k = synthetic_intrinsics(1280, 720);
  k.fx = 1010.5, k.fy = 1008.25, k.cx = 641.3, k.cy = 357.9;
  k.distortion = {-0.21, 0.05, 0.001, -0.002, 0.01};
  write_intrinsics(dir.file("camera.yaml"), k);
  const Intrinsics r = read_intrinsics(dir.file("camera.yaml"));
  EXPECT_EQ(r.width, 1280);
  EXPECT_EQ(r.height, 720);
  EXPECT_DOUBLE_EQ(r.fx, k.fx);
  EXPECT_DOUBLE_EQ(r.fy, k.fy);
  EXPECT_DOUBLE_EQ(r.cx, k.cx);
  EXPECT_DOUBLE_EQ(r.cy, k.cy);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(r.distortion[i], k.distortion[i]) << i;
}

TEST(Camera, IntrinsicsReadRosCameraInfoWithoutSizeOrK3) {
  tests::TempDir dir;
  const std::string f = dir.file("ros.yaml", R"(camera_name: usb_cam
distortion_model: plumb_bob
camera_matrix:
  rows: 3
  cols: 3
  data: [500, 0, 320, 0, 502, 240, 0, 0, 1]
distortion_coefficients:
  rows: 1
  cols: 4
  data: [0.1, -0.2, 0.003, 0.004]
)");
  const Intrinsics k = read_intrinsics(f);
  EXPECT_EQ(k.width, 0);  // from the first frame
  EXPECT_DOUBLE_EQ(k.fy, 502);
  EXPECT_DOUBLE_EQ(k.distortion[3], 0.004);
  EXPECT_DOUBLE_EQ(k.distortion[4], 0);
  EXPECT_EQ(with_frame_size(k, 640, 480, f).width, 640);
  Intrinsics sized = k;
  sized.width = 640, sized.height = 480;
  EXPECT_THROW(with_frame_size(sized, 1280, 720, f), std::invalid_argument);
}

TEST(Camera, BadIntrinsicsFilesNameFileLineAndKey) {
  tests::TempDir dir;
  const auto err = [&](const std::string& text) {
    const std::string f = dir.file("bad.yaml", text);
    return tests::message_of<ConfigError>([&] { read_intrinsics(f); });
  };
  EXPECT_NE(tests::message_of<ConfigError>([&] {
              read_intrinsics(dir.file("missing.yaml"));
            }).find("missing.yaml: cannot be read"),
            std::string::npos);
  EXPECT_NE(err("camera_matrix: [1, 2\n").find("bad.yaml:2:"), std::string::npos);  // syntax error at the end
  EXPECT_NE(err("image_width: 640\n").find("no 'camera_matrix'"), std::string::npos);
  const std::string two_by_three = "camera_matrix:\n  rows: 2\n  cols: 3\n  data: [1, 0, 1, 0, 1, 1]\n";
  EXPECT_TRUE(std::regex_search(err(two_by_three), std::regex("bad\\.yaml:2:[0-9]+: 'camera_matrix' must be 3x3")))
      << err(two_by_three);
  const std::string short_data = "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 1]\n";
  EXPECT_NE(err(short_data).find("bad.yaml:4:"), std::string::npos) << err(short_data);
  const std::string skew = "camera_matrix: {rows: 3, cols: 3, data: [500, 3, 320, 0, 500, 240, 0, 0, 1]}\n";
  EXPECT_NE(err(skew).find("no skew"), std::string::npos);
  const std::string good = "camera_matrix: {rows: 3, cols: 3, data: [500, 0, 320, 0, 500, 240, 0, 0, 1]}\n";
  const std::string rational = good + "distortion_coefficients: {rows: 1, cols: 8, data: [0, 0, 0, 0, 0, 0, 0, 0]}\n";
  EXPECT_TRUE(std::regex_search(err(rational), std::regex("bad\\.yaml:2:[0-9]+: .*4 or 5 coefficients")))
      << err(rational);
  // Sizes that are not small whole numbers: refused before rows x cols is formed.
  const std::string huge = "camera_matrix: {rows: 3.95e13, cols: 3, data: [500, 0, 320, 0, 500, 240, 0, 0, 1]}\n";
  EXPECT_NE(err(huge).find("'camera_matrix' must be 3x3"), std::string::npos) << err(huge);
  const std::string fraction = good + "distortion_coefficients: {rows: 1, cols: 4.5, data: [0, 0, 0, 0]}\n";
  EXPECT_NE(err(fraction).find("4 or 5 coefficients"), std::string::npos) << err(fraction);
  EXPECT_NE(err("distortion_model: equidistant\n" + good).find("bad.yaml:1:"), std::string::npos);
  EXPECT_NE(err("image_width: 640\n" + good).find("both image_width and image_height"), std::string::npos);
  EXPECT_EQ(err(good), "");
}

}  // namespace
}  // namespace hcosim::adapters::vision
