#include "adapters/vision/camera_config.h"

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters::vision {
namespace {

using tests::message_of;

Config params(const std::string& text, const std::string& file = "c.yaml") {
  return Config::parse(text, file, "params");
}

TEST(CameraConfig, ASyntheticCameraHasItsOwnIntrinsicsTruthAndScene) {
  const CameraConfig c = camera_config(
      params("width: 320\nheight: 240\ntag_size: 0.04\nfamily: tag25h9\nframes: off\nquad_decimate: 2\n"), 30);
  ASSERT_NE(c.source, nullptr);
  EXPECT_EQ(c.synthetic, c.source.get());
  EXPECT_EQ(c.intrinsics.width, 320);
  EXPECT_EQ(c.intrinsics.height, 240);
  EXPECT_EQ(c.intrinsics_file, "");
  EXPECT_EQ(c.tracker.tag_size, 0.04);
  EXPECT_EQ(c.tracker.detector.family, "tag25h9");
  EXPECT_EQ(c.tracker.detector.quad_decimate, 2);
  EXPECT_EQ(c.synthetic->camera().marker().family, "tag25h9");  // the camera shows the tag the tracker seeks
  EXPECT_FALSE(c.publish_frames);
  EXPECT_FALSE(c.loop);
  EXPECT_EQ(c.scene.size(), 8u);  // the sheet's corners and half its edge above them
}

// The scene's marker is the tag sought and shown, unless the params say.
TEST(CameraConfig, TheScenesMarkerIsTheTagUnlessTheParamsSay) {
  MarkerSpec marker;
  marker.family = "tag16h5", marker.id = 3, marker.size = 0.03;
  const CameraConfig c = camera_config(params("width: 320\nheight: 240\n"), 30, marker);
  EXPECT_EQ(c.tracker.detector.family, "tag16h5");
  EXPECT_EQ(c.tracker.tag_size, 0.03);
  EXPECT_EQ(c.synthetic->camera().marker().id, 3);
  const CameraConfig own =
      camera_config(params("width: 320\nheight: 240\nfamily: tag25h9\ntag_size: 0.04\ntag_id: 5\n"), 30, marker);
  EXPECT_EQ(own.tracker.detector.family, "tag25h9");
  EXPECT_EQ(own.tracker.tag_size, 0.04);
  EXPECT_EQ(own.synthetic->camera().marker().id, 5);
}

TEST(CameraConfig, FileSourcesNeedTheirFilesAndIntrinsics) {
  tests::TempDir dir;
  const std::string f = dir.file("c.yaml");
  EXPECT_EQ(message_of<ConfigError>([&] { camera_config(params("source: video\n", f), 30); }),
            f + ":1:1: source 'video' needs camera: an intrinsics file in OpenCV's calibration format");
  dir.file("k.yaml",
           "camera_matrix: {rows: 3, cols: 3, data: [500, 0, 320, 0, 500, 240, 0, 0, 1]}\n"
           "distortion_coefficients: {rows: 1, cols: 5, data: [0, 0, 0, 0, 0]}\n");
  EXPECT_EQ(message_of<ConfigError>([&] { camera_config(params("source: folder\ncamera: k.yaml\n", f), 30); }),
            f + ":1:1: source 'folder' needs path: the image folder");
  EXPECT_EQ(message_of<ConfigError>([&] { camera_config(params("source: folder\ncamera: x.yaml\n", f), 30); }),
            f + ":2:9: 'camera': no file " + dir.file("x.yaml"));
}

TEST(CameraConfig, MistakesAreNamedAtTheirPlace) {
  EXPECT_EQ(message_of<ConfigError>([] { camera_config(params("sorce: folder\n"), 30); }),
            "c.yaml:1:1: unknown key 'sorce'; did you mean 'source'?");
  EXPECT_EQ(message_of<ConfigError>([] {
              camera_config(params("family: tag99\n"), 30);
            }).rfind("c.yaml:1:9: 'family' must be one of tag36h11", 0),
            0u);
  EXPECT_EQ(message_of<ConfigError>([] { camera_config(params("orbit: {distance: 0.01}\n"), 30); }),
            "c.yaml:1:19: 'distance' = 0.01 is outside [0.05, 100]");
}

}  // namespace
}  // namespace hcosim::adapters::vision
