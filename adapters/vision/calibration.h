// Camera intrinsics files in OpenCV's calibration format, as OpenCV's
// calibration tools write them (`camera_matrix` and
// `distortion_coefficients` as !!opencv-matrix, `image_width`,
// `image_height`); ROS camera_info files, which use the same keys as plain
// maps, read too.
#pragma once

#include <string>

#include "models/vision/camera.h"

namespace hcosim::adapters::vision {

// The intrinsics in `path`. image_width and image_height may be absent:
// width and height are then 0, to be taken from the first frame
// (with_frame_size). Up to 5 distortion coefficients (k1 k2 p1 p2 k3);
// absent ones are 0. Throws ConfigError naming FILE:LINE:COL and the key.
models::vision::Intrinsics read_intrinsics(const std::string& path);

// Writes `k` with cv::FileStorage, in the format read_intrinsics reads.
// Throws std::runtime_error when the file cannot be written.
void write_intrinsics(const std::string& path, const models::vision::Intrinsics& k);

// `k` for frames of width x height: unchanged when its size is known and
// equal, given that size when it is 0; throws std::invalid_argument naming
// `path` when the calibrated size differs (intrinsics hold for one size).
models::vision::Intrinsics with_frame_size(models::vision::Intrinsics k, int width, int height,
                                           const std::string& path);

}  // namespace hcosim::adapters::vision
