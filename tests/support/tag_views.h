// Views of the synthetic camera's tag for the vision tests: poses tilted
// and turned from facing the tag, and the worst corner error of a detection.
#pragma once

#include <algorithm>
#include <vector>

#include <Eigen/Geometry>

#include "models/vision/detector.h"
#include "models/vision/synthetic.h"

namespace hcosim::tests {

inline constexpr double kDeg = 3.14159265358979323846 / 180;

// `distance` m in front of the tag, tilted about its x axis and turned about
// its normal (degrees), moved `x` m sideways.
inline Eigen::Isometry3d tilted(double distance, double tilt_deg, double turn_deg, double x = 0) {
  Eigen::Isometry3d p = models::vision::facing(distance);
  p.linear() = p.linear() * Eigen::AngleAxisd(tilt_deg * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix() *
               Eigen::AngleAxisd(turn_deg * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation().x() = x;
  return p;
}

inline double max_corner_error(const models::vision::Detection& d, const std::vector<Eigen::Vector2d>& truth) {
  double worst = 0;
  for (std::size_t i = 0; i < 4; ++i) worst = std::max(worst, (d.corners[i] - truth[i]).norm());
  return worst;
}

}  // namespace hcosim::tests
