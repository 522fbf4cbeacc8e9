// The AR view without DDS: a body on the marker is drawn over the frame
// where the marker's pose puts it, and nothing without a pose; the video
// gets a frame for each the camera numbered; pictures are taken at their
// moments; each source's force becomes a trace and its plot.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "adapters/vision/vision_idl.h"
#include "services/ar_view/compositor.h"
#include "tests/support/samples.h"
#include "tests/support/temp_dir.h"

namespace hcosim::services::ar_view {
namespace {

namespace fs = std::filesystem;

adapters::render::ViewConfig config(const std::string& extra = "") {
  return adapters::render::view_config(
      adapters::Config::parse("objects: [{name: ball, kind: rigid, size: 0.02}]\n" + extra, "v.yaml", "params"), 25);
}

// Millisecond steps.
StepStamp stamp(std::int64_t ms) { return tests::stamp(std::uint64_t(ms)); }

// A grey 320 x 240 frame of camera "cam", numbered `frame`, at `ms`.
CameraFrame frame(std::uint64_t n, std::int64_t ms) {
  models::vision::Intrinsics k;
  k.width = 320, k.height = 240, k.fx = k.fy = 300, k.cx = 159.5, k.cy = 119.5;
  return adapters::vision::camera_frame("cam", stamp(ms), n, cv::Mat(240, 320, CV_8UC3, cv::Scalar(100, 100, 100)), k);
}

// The marker 30 cm in front of the camera, facing it.
MarkerPose pose(std::uint64_t n) {
  MarkerPose p;
  p.camera("cam");
  p.tag_id(0);
  p.frame(n);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  t.translation() = Eigen::Vector3d(0, 0, 0.3);
  p.tag_in_camera(adapters::vision::to_idl(t));
  return p;
}

RigidBodyState ball() {
  RigidBodyState b;
  b.body("ball");
  b.shape("sphere");
  b.pose().position().z(0.02);
  b.pose().orientation().w(1.0);
  return b;
}

// Pixels of the last frame drawn that are not the frame's grey.
int drawn(const Compositor& c) {
  cv::Mat diff;
  cv::absdiff(c.composite(), cv::Scalar(100, 100, 100), diff);
  cv::Mat grey;
  cv::extractChannel(diff, grey, 0);
  return cv::countNonZero(grey > 20);
}

TEST(Compositor, ABodyIsDrawnWhereTheMarkersPosePutsItAndNothingWithoutOne) {
  tests::TempDir dir;
  Compositor view(config("video: ''\nplots: off\nstylus: off\n"), dir.path, "view");
  view.on(ball());
  view.on(frame(0, 0));
  const int without = drawn(view);
  view.on(pose(1));
  view.on(frame(1, 40));
  const int with = drawn(view);
  EXPECT_LT(without, 2000) << "only the time is written over a frame without a pose";
  // A 2 cm ball 28 cm away through a 300 px focal length: about 40 px across.
  EXPECT_GT(with - without, 800);
  EXPECT_EQ(view.rendered(), 2u);
}

TEST(Compositor, TheVideoKeepsTheCamerasTimeAndPicturesAndPlotsAreWritten) {
  tests::TempDir dir;
  Compositor view(config("snapshots: [0.1]\nvideo: ar.mp4\n"), dir.path, "view");
  view.on(pose(0));
  view.on(frame(0, 0));
  ForceFeedback f;
  f.source("ball");
  f.device("omni");
  f.force().z(0.5);
  f.penetration_m(0.001);
  for (int ms = 0; ms < 80; ++ms) {
    f.stamp(stamp(ms));
    view.on(f);
  }
  view.on(frame(3, 120));  // frames 1 and 2 were never sent
  const std::string said = tests::written([&](std::FILE* log) { view.finish(log); });
  EXPECT_NE(said.find("view: 2 frames drawn, 2 skipped"), std::string::npos) << said;
  EXPECT_NE(said.find(", 4 frames"), std::string::npos) << said;
  EXPECT_TRUE(fs::exists(dir.path / "ar.mp4"));
  EXPECT_TRUE(fs::exists(dir.path / "snapshots" / "ar_000.1s.png")) << said;
  EXPECT_TRUE(fs::exists(dir.path / "plots" / "ball.png"));
  EXPECT_TRUE(fs::exists(dir.path / "plots" / "all.png"));
  ASSERT_EQ(view.traces().count("ball"), 1u);
  EXPECT_EQ(view.traces().at("ball").t.size(), 80u);
}

TEST(Compositor, ATraceKeepsItsPeaksInBoundedMemory) {
  Trace t;
  for (std::size_t k = 0; k < 3 * Trace::kPoints; ++k) t.add(k * 1e-3, k == 12345 ? 9.0 : 1.0, 0);
  EXPECT_LT(t.t.size(), Trace::kPoints);
  EXPECT_EQ(*std::max_element(t.force.begin(), t.force.end()), 9.0);
  EXPECT_GT(t.t.back(), 0.9 * 3 * Trace::kPoints * 1e-3);
}

}  // namespace
}  // namespace hcosim::services::ar_view
