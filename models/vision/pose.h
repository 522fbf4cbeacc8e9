// A tag's pose from its four corners: OpenCV's IPPE for squares (both
// solutions of the planar two-fold ambiguity), the ambiguity resolved by
// reprojection error or, when both fit about equally, by the previous pose
// of the same tag; then optionally refined by Levenberg-Marquardt on the
// reprojection error.
#pragma once

#include <array>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "models/vision/camera.h"

namespace hcosim::models::vision {

struct PoseOptions {
  bool refine = true;            // Levenberg-Marquardt on the reprojection error after IPPE
  double ambiguity_ratio = 1.5;  // the two IPPE solutions are ambiguous when their errors are within this ratio
};

struct TagPose {
  Eigen::Isometry3d tag_in_camera = Eigen::Isometry3d::Identity();  // tag frame to camera frame, m
  double reprojection_error_px = 0;                                 // RMS over the corners
  bool ambiguous = false;  // the other IPPE solution fit within ambiguity_ratio
};

// The pose of a tag of black-border edge `tag_size` (m) from its corners
// (px, the order of detector.h), through a camera of intrinsics k. With a
// prior (this tag's previous pose) an ambiguous pair is decided by which
// solution turns less from it. Throws std::invalid_argument for a bad
// size or non-finite corners.
TagPose estimate_pose(const std::array<Eigen::Vector2d, 4>& corners, double tag_size, const Intrinsics& k,
                      const PoseOptions& options = {}, const std::optional<Eigen::Isometry3d>& prior = std::nullopt);

// Rotation angle between two orientations, rad.
double angle_between(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace hcosim::models::vision
