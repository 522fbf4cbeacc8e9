// Conversions between the tracker's results and frames and the MarkerPose
// and CameraFrame topics.
#pragma once

#include <cstdint>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "idl/vision.h"
#include "models/vision/tracker.h"

namespace hcosim::adapters::vision {

Transform to_idl(const Eigen::Isometry3d& pose);
// The rotation of a Quat (normalised) and the pose of a Transform.
Eigen::Matrix3d from_idl(const Quat& q);
Eigen::Isometry3d from_idl(const Transform& t);

// Observation o of frame `frame` from camera `camera`, published
// `latency_ms` after the frame was captured.
MarkerPose marker_pose(const std::string& camera, const std::string& family, const StepStamp& stamp,
                       std::uint64_t frame, double tag_size, const models::vision::Observation& o, double latency_ms);

// A CV_8UC1 (mono8) or CV_8UC3 (bgr8) image with its intrinsics. Throws
// std::invalid_argument for another type.
CameraFrame camera_frame(const std::string& camera, const StepStamp& stamp, std::uint64_t frame, const cv::Mat& image,
                         const models::vision::Intrinsics& k);

// A frame's pixels as 8-bit BGR (mono8 converted) and its intrinsics.
// Throws std::invalid_argument for a frame validate() would refuse.
cv::Mat bgr_image(const CameraFrame& f);
// Its pixels where they lie, CV_8UC3 (bgr8) or CV_8UC1 (mono8), not to be
// written to: valid while `f` is. Throws as bgr_image.
cv::Mat pixels(const CameraFrame& f);
models::vision::Intrinsics intrinsics(const CameraFrame& f);

}  // namespace hcosim::adapters::vision
