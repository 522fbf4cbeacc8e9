// The tracker's inputs: intrinsics files as OpenCV writes them and as ROS
// writes them, with located errors for bad ones; image folders in name
// order, skipping what is not an image and naming what does not decode;
// video files; a missing live camera; the synthetic source's truth; and
// the tracker on the frames they give.
#include <filesystem>
#include <fstream>
#include <regex>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "adapters/config.h"
#include "adapters/vision/calibration.h"
#include "adapters/vision/source.h"
#include "models/vision/tracker.h"

namespace hcosim::adapters::vision {

// The vision models these sources and files carry.
using namespace models::vision;
namespace {

namespace fs = std::filesystem;

// A fresh folder under the system's temporary folder, removed at the end.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("hcosim_camera_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name, const std::string& text = "") const {
    const fs::path p = path / name;
    if (!text.empty()) std::ofstream(p) << text;
    return p.string();
  }
};

// The message of the ConfigError `f` throws; "" when it throws none.
template <class F>
std::string config_error(F f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Camera, IntrinsicsReadBackWhatOpenCvWrites) {
  TempDir dir;
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
  TempDir dir;
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
  TempDir dir;
  const auto err = [&](const std::string& text) {
    const std::string f = dir.file("bad.yaml", text);
    return config_error([&] { read_intrinsics(f); });
  };
  EXPECT_NE(config_error([&] { read_intrinsics(dir.file("missing.yaml")); }).find("missing.yaml: cannot be read"),
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

TEST(Camera, FolderGivesImagesInNameOrderAndNamesWhatDoesNotDecode) {
  TempDir dir;
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

  TempDir empty;
  empty.file("readme.md", "nothing here");
  EXPECT_THROW(open_folder(empty.path.string()), std::runtime_error);
  EXPECT_THROW(open_folder((empty.path / "absent").string()), std::runtime_error);
}

TEST(Camera, VideoFilesPlayInOrderAndUnreadableOnesAreRefused) {
  TempDir dir;
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

}  // namespace
}  // namespace hcosim::adapters::vision
