// AprilTag 3 detection: libapriltag with its parameters, on 8-bit grey
// frames. Corners are returned in the tag frame's order of
// SyntheticCamera::corners: (-s/2, -s/2), (s/2, -s/2), (s/2, s/2),
// (-s/2, s/2), with the tag frame x right, y up, z toward the camera.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "models/vision/tag.h"

struct apriltag_detector;

namespace hcosim::models::vision {

struct DetectorParams {
  std::string family = "tag36h11";
  double quad_decimate = 1.5;  // detect quads on a frame this many times smaller (1: full; libapriltag: 2)
  double quad_sigma = 0;       // px, Gaussian blur before quad detection (negative: sharpen)
  int nthreads = 1;
  bool refine_edges = true;  // snap quad edges to the strongest gradient at full resolution
  double decode_sharpening = 0.25;
  int max_hamming = 1;         // bit errors corrected; more finds damaged tags and more false ones
  bool refine_corners = true;  // refit each border edge to its sub-pixel edge points (below)
};

// Throws std::invalid_argument naming the bad parameter.
void check(const DetectorParams& p);

struct Detection {
  int id = 0;
  int hamming = 0;
  double decision_margin = 0;
  std::array<Eigen::Vector2d, 4> corners;  // px, order above
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
};

// Corners refitted to the tag's black border: along each edge, away from
// the corners, the profile across the edge is sampled at quarter pixels
// and the point where it crosses the level midway between the black
// inside and the white outside is taken as the edge (exact for any
// symmetric blur); a line is fitted to those points and the corners are
// the lines' intersections. `cells` is the family's border width in
// cells: the profile stays within one cell of the edge. Corners whose
// edges are too short or too faint to refit are returned unchanged.
std::array<Eigen::Vector2d, 4> refine_corners(const cv::Mat& grey, const std::array<Eigen::Vector2d, 4>& corners,
                                              int cells);

class Detector {
 public:
  explicit Detector(const DetectorParams& p);
  ~Detector();
  Detector(const Detector&) = delete;
  Detector& operator=(const Detector&) = delete;

  // Every tag in a CV_8UC1 frame; throws std::invalid_argument for another type.
  std::vector<Detection> detect(const cv::Mat& grey) const;
  const DetectorParams& params() const { return params_; }

 private:
  DetectorParams params_;
  Family family_;
  apriltag_detector* detector_ = nullptr;
};

}  // namespace hcosim::models::vision
