#include "haptic/force_sum.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::haptic {

ForceSum::ForceSum(double timeout_s) : timeout_(timeout_s) {
  if (!(timeout_s > 0) || !std::isfinite(timeout_s)) throw std::invalid_argument("force sum: timeout must be finite and > 0");
}

void ForceSum::set(const std::string& source, const Eigen::Vector3d& force, double t) { latest_[source] = {force, t}; }

Eigen::Vector3d ForceSum::total(double t) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto it = latest_.begin(); it != latest_.end();) {
    if (t - it->second.t > timeout_) {
      it = latest_.erase(it);
      ++expired_;
      continue;
    }
    sum += it->second.force;
    ++it;
  }
  return sum;
}

}  // namespace hcosim::haptic
