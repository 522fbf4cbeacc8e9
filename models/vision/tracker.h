// The marker tracker: every tag in a frame, detected and posed, each tag's
// two-fold ambiguity settled by its own previous pose. Deterministic in the
// sequence of frames it is given.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include <opencv2/core.hpp>

#include "models/vision/camera.h"
#include "models/vision/detector.h"
#include "models/vision/pose.h"

namespace hcosim::models::vision {

struct TrackerParams {
  DetectorParams detector;
  PoseOptions pose;
  double tag_size = 0.05;  // m, black-border edge of every tag
};

// Throws std::invalid_argument naming the bad parameter.
void check(const TrackerParams& p);

struct Observation {
  Detection detection;
  TagPose pose;
};

class Tracker {
 public:
  // Throws std::invalid_argument for bad parameters or intrinsics.
  Tracker(const TrackerParams& p, const Intrinsics& k);

  // The tags in one frame (CV_8UC1 grey, or CV_8UC3 BGR converted here),
  // in increasing id; a tag whose corners no pose fits is left out and
  // counted in unposed(). Throws std::invalid_argument for a frame of
  // another type or of a size other than the intrinsics'.
  std::vector<Observation> track(const cv::Mat& frame);
  std::uint64_t unposed() const { return unposed_; }

  const TrackerParams& params() const { return params_; }
  const Intrinsics& intrinsics() const { return k_; }

 private:
  TrackerParams params_;
  Intrinsics k_;
  Detector detector_;
  std::map<int, Eigen::Isometry3d> last_;  // each tag's latest pose: the prior of its next
  std::uint64_t unposed_ = 0;
};

}  // namespace hcosim::models::vision
