// The marker tracking service's step without DDS: a synthetic camera's tag
// is posed in every frame, close to the truth, as admissible MarkerPose
// samples with the frame they came from; an image folder with a file that
// does not decode skips it and goes on, and ends with its last image.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "adapters/validate.h"
#include "adapters/vision/media.h"
#include "services/tracker/frame_tracker.h"
#include "tests/support/samples.h"
#include "tests/support/temp_dir.h"

namespace hcosim::services::tracker {
namespace {

// Steps of a 25 Hz camera.
StepStamp stamp(std::uint64_t step) { return tests::stamp(step, 40'000'000); }

std::string report_of(const FrameTracker& t) {
  return tests::written([&](std::FILE* out) { t.report(out); });
}

TEST(FrameTracker, ASyntheticTagIsPosedInEveryFrameNearItsTruth) {
  FrameTracker t(
      adapters::vision::camera_config(adapters::Config::parse("width: 640\nheight: 480\n", "c.yaml", "params"), 25),
      "cam", stderr);
  for (std::uint64_t k = 0; k < 10; ++k) {
    ASSERT_TRUE(t.step(stamp(k)));
    ASSERT_EQ(t.poses().size(), 1u) << "frame " << k;
    const MarkerPose& m = t.poses()[0];
    EXPECT_EQ(m.camera().to_string(), "cam");
    EXPECT_EQ(m.frame(), k);
    EXPECT_EQ(m.stamp().step(), k);
    EXPECT_EQ(adapters::validate(m), std::nullopt);
    ASSERT_TRUE(t.has_frame());
    const CameraFrame f = t.frame(stamp(k));
    EXPECT_EQ(f.width(), 640u);
    EXPECT_EQ(f.frame(), k);
  }
  const std::string said = report_of(t);
  EXPECT_NE(said.find("cam: 10 frames, 10 with a tag, 10 detections"), std::string::npos) << said;
  EXPECT_NE(said.find("against the synthetic truth: translation error p50 0."), std::string::npos) << said;
}

TEST(FrameTracker, AFolderSkipsWhatDoesNotDecodeAndEnds) {
  tests::TempDir dir;
  const std::string images = (dir.path / "images").string();
  std::filesystem::create_directories(images);
  adapters::vision::write_image(images + "/0.png", cv::Mat(240, 320, CV_8UC1, cv::Scalar(128)));
  dir.file("images/1.png", "not a picture");
  adapters::vision::write_image(images + "/2.png", cv::Mat(240, 320, CV_8UC1, cv::Scalar(128)));
  dir.file("k.yaml",
           "camera_matrix: {rows: 3, cols: 3, data: [300, 0, 160, 0, 300, 120, 0, 0, 1]}\n"
           "distortion_coefficients: {rows: 1, cols: 5, data: [0, 0, 0, 0, 0]}\n"
           "image_width: 320\nimage_height: 240\n");
  FrameTracker t(
      adapters::vision::camera_config(
          adapters::Config::parse("source: folder\npath: images\ncamera: k.yaml\n", dir.file("c.yaml"), "params"), 25),
      "cam", stderr);
  int with_frame = 0;
  for (std::uint64_t k = 0; k < 3; ++k) {
    ASSERT_TRUE(t.step(stamp(k))) << k;
    EXPECT_TRUE(t.poses().empty()) << "no tag in a grey image";
    with_frame += t.has_frame();
  }
  EXPECT_EQ(with_frame, 2);
  EXPECT_FALSE(t.step(stamp(3)));
  EXPECT_FALSE(t.step(stamp(4)));
  EXPECT_NE(report_of(t).find("cam: 3 frames, 0 with a tag, 0 detections"), std::string::npos) << report_of(t);
  EXPECT_NE(report_of(t).find("1 unreadable"), std::string::npos) << report_of(t);
}

}  // namespace
}  // namespace hcosim::services::tracker
