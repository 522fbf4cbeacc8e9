#include "models/vision/tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace hcosim::models::vision {

void check(const TrackerParams& p) {
  check(p.detector);
  if (!(p.tag_size > 0 && p.tag_size <= 10)) throw std::invalid_argument("tracker: tag_size must be in (0, 10] m");
  if (!(p.pose.ambiguity_ratio >= 1 && std::isfinite(p.pose.ambiguity_ratio)))
    throw std::invalid_argument("tracker: ambiguity_ratio must be at least 1");
}

Tracker::Tracker(const TrackerParams& p, const Intrinsics& k) : params_(p), k_(k), detector_(p.detector) {
  check(p);
  check(k);
}

std::vector<Observation> Tracker::track(const cv::Mat& frame) {
  if (frame.cols != k_.width || frame.rows != k_.height)
    throw std::invalid_argument("tracker: a " + std::to_string(frame.cols) + "x" + std::to_string(frame.rows) +
                                " frame from a camera calibrated at " + std::to_string(k_.width) + "x" +
                                std::to_string(k_.height));
  cv::Mat grey;
  if (frame.type() == CV_8UC3)
    cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
  else if (frame.type() == CV_8UC1)
    grey = frame;
  else
    throw std::invalid_argument("tracker: frames must be 8-bit grey or BGR");
  std::vector<Observation> out;
  for (const Detection& d : detector_.detect(grey)) {
    const auto prior = last_.find(d.id);
    Observation o{d, {}};
    try {
      o.pose = estimate_pose(d.corners, params_.tag_size, k_, params_.pose,
                             prior == last_.end() ? std::nullopt : std::optional(prior->second));
    } catch (const std::invalid_argument&) {
      // Corners no pose fits (a degenerate quad): the tag is not reported.
      ++unposed_;
      continue;
    }
    last_[d.id] = o.pose.tag_in_camera;
    out.push_back(o);
  }
  std::sort(out.begin(), out.end(),
            [](const Observation& a, const Observation& b) { return a.detection.id < b.detection.id; });
  return out;
}

}  // namespace hcosim::models::vision
