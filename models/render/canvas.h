// Drawing virtual objects over a camera frame: triangle meshes with a
// depth test and shading, seen through the camera that took the frame.
// The AR view's renderer; headless (OpenCV images, no display).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "models/vision/camera.h"

namespace hcosim::models::render {

class Canvas {
 public:
  // Draws into `bgr` (CV_8UC3, the intrinsics' size; shared, not copied),
  // seen from a camera at `world_in_camera` (the marker's pose in the
  // camera: MarkerPose.tag_in_camera). Throws std::invalid_argument for
  // another image type or size.
  Canvas(cv::Mat bgr, const models::vision::Intrinsics& k, const Eigen::Isometry3d& world_in_camera);

  // The triangles (3 vertex indices each) of `vertices` (3 x n, world
  // frame, m) in `colour`, shaded by how squarely each faces the camera
  // (both sides lit); parts behind what is already drawn are hidden.
  // Triangles reaching closer than 1 cm to the camera are skipped.
  // Throws std::invalid_argument for an index out of range.
  void mesh(const Eigen::Matrix3Xd& vertices, const std::vector<std::uint32_t>& triangles, const cv::Scalar& colour);

  // A straight arrow from one world point to another, drawn over
  // everything (no depth test); nothing when either end is behind the camera.
  void arrow(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const cv::Scalar& colour, int thickness);

  // A world point's pixel, and its depth along the optical axis (m).
  Eigen::Vector2d project(const Eigen::Vector3d& world, double* depth = nullptr) const;

  // Pixels drawn so far.
  std::uint64_t pixels() const { return pixels_; }
  const cv::Mat& image() const { return bgr_; }

 private:
  cv::Mat bgr_;
  cv::Mat depth_;  // CV_32F, m; +inf where nothing is drawn
  models::vision::Intrinsics k_;
  Eigen::Isometry3d world_in_camera_;
  std::uint64_t pixels_ = 0;
};

}  // namespace hcosim::models::render
