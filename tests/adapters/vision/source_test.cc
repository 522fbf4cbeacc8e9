// Camera sources: image folders in name order, skipping what is not an
// image and naming what does not decode; video files; a missing live camera;
// the synthetic source's truth; the tracker on the frames they give, and its
// registration error along the default deployment's orbit.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "adapters/vision/source.h"
#include "models/vision/synthetic.h"
#include "models/vision/tracker.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::vision {

using namespace models::vision;
namespace {

namespace fs = std::filesystem;

TEST(Camera, FolderGivesImagesInNameOrderAndNamesWhatDoesNotDecode) {
  tests::TempDir dir;
  for (const char* name : {"b.png", "a.png", "c.png"}) {
    cv::Mat img(48, 64, CV_8UC1, cv::Scalar(name[0]));
    ASSERT_TRUE(cv::imwrite(dir.file(name), img));
  }
  dir.file("notes.txt", "not an image");
  dir.file("d.png", "not a png either");
  std::unique_ptr<Source> s = open_path(dir.path.string());
  EXPECT_NE(s->describe().find("4 images, 1 other files ignored"), std::string::npos) << s->describe();
  Frame f;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(s->next(f));
    EXPECT_EQ(f.index, std::uint64_t(i));
    ASSERT_EQ(f.image.type(), CV_8UC1);
    EXPECT_EQ(f.image.at<std::uint8_t>(0, 0), 'a' + i);
  }
  ASSERT_TRUE(s->next(f));
  EXPECT_TRUE(f.image.empty());
  EXPECT_NE(f.problem.find("d.png: cannot be read as an image"), std::string::npos) << f.problem;
  EXPECT_FALSE(s->next(f));
  ASSERT_TRUE(s->rewind());
  ASSERT_TRUE(s->next(f));
  EXPECT_EQ(f.image.at<std::uint8_t>(0, 0), 'a');

  tests::TempDir empty;
  empty.file("readme.md", "nothing here");
  EXPECT_THROW(open_folder(empty.path.string()), std::runtime_error);
  EXPECT_THROW(open_folder((empty.path / "absent").string()), std::runtime_error);
}

TEST(Camera, VideoFilesPlayInOrderAndUnreadableOnesAreRefused) {
  tests::TempDir dir;
  const std::string file = dir.file("clip.avi");
  cv::VideoWriter w(file, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25, cv::Size(64, 48), true);
  ASSERT_TRUE(w.isOpened());
  for (int i = 0; i < 5; ++i) w.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar(40 * i, 40 * i, 40 * i)));
  w.release();
  std::unique_ptr<Source> s = open_path(file);
  Frame f;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(s->next(f)) << i;
    EXPECT_EQ(f.index, std::uint64_t(i));
    EXPECT_NEAR(f.image.at<cv::Vec3b>(24, 32)[0], 40 * i, 4) << i;  // JPEG is lossy
  }
  EXPECT_FALSE(s->next(f));
  ASSERT_TRUE(s->rewind());
  ASSERT_TRUE(s->next(f));
  EXPECT_EQ(f.index, 0u);

  try {
    open_video(dir.file("fake.mp4", "just text"));
    ADD_FAILURE() << "a text file opened as a video";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("fake.mp4: OpenCV cannot open it as a video"), std::string::npos) << e.what();
  }
  EXPECT_THROW(open_video(dir.file("absent.avi")), std::runtime_error);
}

TEST(Camera, MissingLiveCameraSaysSo) {
  try {
    open_v4l2("/dev/video_hcosim_absent", 640, 480, 30);
    ADD_FAILURE() << "a missing camera opened";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "V4L2 camera /dev/video_hcosim_absent: no such device");
  }
}

TEST(Camera, SyntheticSourceFollowsItsOrbitAndRendersTheSameTwice) {
  const SyntheticCamera cam(synthetic_intrinsics(640, 480), Marker{});
  SyntheticSource a(cam, condition("noisy"), 25, 3), b(cam, condition("noisy"), 25, 3);
  Frame fa, fb;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(a.next(fa) && b.next(fb));
    EXPECT_EQ(cv::norm(fa.image, fb.image, cv::NORM_INF), 0) << i;
    EXPECT_TRUE(a.truth(fa.index).isApprox(orbit(i / 25.0)));
  }
  EXPECT_FALSE(a.next(fa));
  EXPECT_THROW(SyntheticSource(cam, {}, 0), std::invalid_argument);
}

TEST(Camera, TrackerFollowsTheSyntheticTagInGreyAndColour) {
  const Intrinsics k = synthetic_intrinsics(640, 480);
  SyntheticSource s(SyntheticCamera(k, Marker{}), {}, 2, 20);  // 10 s of the orbit: tilts up to 30 degrees
  Tracker grey({}, k), colour({}, k);
  for (Frame f; s.next(f);) {
    const auto a = grey.track(f.image);
    cv::Mat bgr;
    cv::cvtColor(f.image, bgr, cv::COLOR_GRAY2BGR);
    const auto b = colour.track(bgr);
    ASSERT_EQ(a.size(), 1u) << f.index;
    ASSERT_EQ(b.size(), 1u) << f.index;
    const Eigen::Isometry3d truth = s.truth(f.index);
    EXPECT_LT((a[0].pose.tag_in_camera.translation() - truth.translation()).norm(), 0.003 * truth.translation().norm())
        << f.index;
    EXPECT_LT(angle_between(a[0].pose.tag_in_camera.linear(), truth.linear()), 3 * M_PI / 180) << f.index;
    EXPECT_TRUE(a[0].pose.tag_in_camera.isApprox(b[0].pose.tag_in_camera, 1e-9)) << f.index;
  }
  EXPECT_THROW(grey.track(cv::Mat(720, 1280, CV_8UC1, cv::Scalar(255))), std::invalid_argument);
  EXPECT_THROW(grey.track(cv::Mat(480, 640, CV_32FC1, cv::Scalar(1))), std::invalid_argument);
  TrackerParams bad;
  bad.tag_size = 0;
  EXPECT_THROW(Tracker(bad, k), std::invalid_argument);
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

}  // namespace
}  // namespace hcosim::adapters::vision
