// The synthetic camera: the marker (a tag on a white sheet lying in the
// plane z = 0 of the tag frame) seen by a pinhole camera at a known pose,
// rendered with 3x3 supersampling, with optional noise, blur, lighting
// change and an occluding bar. It is the ground truth of the tracker's
// tests and benchmark.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "models/vision/camera.h"
#include "models/vision/tag.h"

namespace hcosim::models::vision {

struct Marker {
  std::string family = "tag36h11";
  int id = 0;
  double tag_size = 0.05;  // m, edge of the black border
  double sheet = 2.0;      // edge of the white sheet around the tag, in tag sizes, >= 1.25
};

struct Conditions {
  double noise = 0;      // grey levels, standard deviation of Gaussian noise
  double blur = 0;       // px, standard deviation of a Gaussian blur (0: none)
  double gain = 1;       // lighting: every grey level times gain ...
  double offset = 0;     // ... plus offset ...
  double gradient = 0;   // ... plus gradient times (x / width - 1/2) times 255
  double occlusion = 0;  // fraction of the tag's width covered by a bar from its left edge, [0, 1]
};

// Named conditions of the benchmark: clean, noisy (sigma 6 grey levels),
// blurred (sigma 1.2 px); throws std::invalid_argument for another name.
Conditions condition(const std::string& name);

class SyntheticCamera {
 public:
  // Throws std::invalid_argument for bad intrinsics or a bad marker.
  SyntheticCamera(const Intrinsics& k, const Marker& m);

  // The 8-bit grey frame of the marker at `tag_in_camera`; `seed` drives the noise.
  cv::Mat render(const Eigen::Isometry3d& tag_in_camera, const Conditions& c = {}, std::uint64_t seed = 0) const;

  // The tag's black-border corners in the image (px), in the order
  // (-s/2, -s/2), (s/2, -s/2), (s/2, s/2), (-s/2, s/2) of the tag frame.
  std::vector<Eigen::Vector2d> corners(const Eigen::Isometry3d& tag_in_camera) const;

  const Intrinsics& intrinsics() const { return k_; }
  const Marker& marker() const { return m_; }

 private:
  // The output pixels the sheet can touch under the supersampled
  // homography H (texel to supersampled pixel).
  cv::Rect footprint(const Eigen::Matrix3d& H) const;

  Intrinsics k_;
  Marker m_;
  cv::Mat texture_;  // the sheet, CV_8U
  double metres_per_texel_ = 0;
  cv::Mat map_x_, map_y_;  // distortion: for each image pixel, where it lies undistorted
};

// n poses of the tag in the camera, each with the whole sheet's tag in the
// frame (corners at least 8 px inside): distance uniform in [near, far] m,
// tilt uniform up to max_tilt_deg about a random axis in the tag plane, a
// random turn about the tag's normal. Deterministic in `seed`.
std::vector<Eigen::Isometry3d> random_poses(const Intrinsics& k, double tag_size, int n, std::uint64_t seed,
                                            double near = 0.15, double far = 0.7, double max_tilt_deg = 55);

// The tag facing the camera at `distance` m, upright in the image.
Eigen::Isometry3d facing(double distance);

// A slow, smooth camera motion for the live synthetic source, aimed at the
// tag's centre. The default is the tracker's test motion: distance
// 0.25..0.45 m, tilt up to 30 degrees about an axis turning once in 20 s.
// An AR scene wants what a person at the table sees: `upright`, the
// camera on the tag's -y side with the image's up toward the tag's +z,
// swaying `sweep_deg` around it, seen from a base tilt.
struct Orbit {
  double distance = 0.35;    // m, mean distance to the tag's centre, > 0
  double swing = 0.1;        // m, amplitude of the distance, < distance
  double tilt_deg = 30;      // degrees, amplitude of the tilt added to base_tilt_deg
  double base_tilt_deg = 0;  // degrees; base + amplitude < 80
  double period = 20;        // s, > 0
  bool upright = false;
  double sweep_deg = 0;  // upright: degrees of sway about the tag's normal, < 180
};

// Throws std::invalid_argument naming the first bad field.
void check(const Orbit& o);

// The tag in the camera at time t (s), phase = 2 pi t / period: distance
// d + swing sin(phase), tilt (from the tag's normal) base + amplitude
// sin(phase / 2). Not upright: about an axis in the tag plane at angle
// phase. Upright: the camera at azimuth -90 + sweep sin(phase) degrees.
Eigen::Isometry3d orbit(double t, const Orbit& o = {});

// The largest distance (px) between where `points` (tag frame, m) appear
// under an estimated and the true pose of the tag in the camera: how far
// virtual objects at those points are drawn from where they belong.
double registration_error_px(const Intrinsics& k, const Eigen::Isometry3d& estimated, const Eigen::Isometry3d& truth,
                             const std::vector<Eigen::Vector3d>& points);

}  // namespace hcosim::models::vision
