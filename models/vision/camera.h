// A pinhole camera with OpenCV's distortion model, and the frames the
// tracker works in: the tag's (the AR marker's, docs/topics.md: x right,
// y up, z out of the marker toward the camera) and the camera's (OpenCV:
// x right, y down, z forward). Pixel centres are at integer coordinates.
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

namespace hcosim::models::vision {

struct Intrinsics {
  int width = 640, height = 480;       // px
  double fx = 600, fy = 600;           // focal lengths, px
  double cx = 319.5, cy = 239.5;       // principal point, px
  std::array<double, 5> distortion{};  // k1 k2 p1 p2 k3 (OpenCV order)
};

// Throws std::invalid_argument naming the bad field.
void check(const Intrinsics& k);

// The synthetic camera's intrinsics for a frame size: focal length
// 0.9375 width (600 px at 640 wide, a 56 degree horizontal field of view),
// principal point at the centre, no distortion.
Intrinsics synthetic_intrinsics(int width, int height);

cv::Matx33d camera_matrix(const Intrinsics& k);
cv::Mat distortion(const Intrinsics& k);  // 1x5, CV_64F

// Where the tag frame's point p (m) appears, for the tag at `tag_in_camera`.
Eigen::Vector2d project(const Intrinsics& k, const Eigen::Isometry3d& tag_in_camera, const Eigen::Vector3d& p);

}  // namespace hcosim::models::vision
