#include "models/vision/camera.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>

namespace hcosim::models::vision {

void check(const Intrinsics& k) {
  if (k.width < 16 || k.height < 16 || k.width > 8192 || k.height > 8192)
    throw std::invalid_argument("camera: image size " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                                " is outside 16x16 .. 8192x8192");
  if (!(k.fx > 0 && k.fy > 0 && std::isfinite(k.fx) && std::isfinite(k.fy)))
    throw std::invalid_argument("camera: focal lengths must be finite and > 0");
  if (!(std::isfinite(k.cx) && std::isfinite(k.cy)))
    throw std::invalid_argument("camera: principal point is not finite");
  for (double d : k.distortion)
    if (!std::isfinite(d) || std::abs(d) > 1e3)
      throw std::invalid_argument("camera: a distortion coefficient is absurd");
}

Intrinsics synthetic_intrinsics(int width, int height) {
  Intrinsics k;
  k.width = width, k.height = height;
  k.fx = k.fy = 0.9375 * width;
  k.cx = 0.5 * (width - 1), k.cy = 0.5 * (height - 1);
  check(k);
  return k;
}

cv::Matx33d camera_matrix(const Intrinsics& k) { return {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}; }

cv::Mat distortion(const Intrinsics& k) {
  return cv::Mat(1, 5, CV_64F, const_cast<double*>(k.distortion.data())).clone();
}

Eigen::Vector2d project(const Intrinsics& k, const Eigen::Isometry3d& tag_in_camera, const Eigen::Vector3d& p) {
  const Eigen::Vector3d c = tag_in_camera * p;
  std::vector<cv::Point3d> in{{c.x(), c.y(), c.z()}};
  std::vector<cv::Point2d> out;
  cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix(k), distortion(k), out);
  return {out[0].x, out[0].y};
}

}  // namespace hcosim::models::vision
