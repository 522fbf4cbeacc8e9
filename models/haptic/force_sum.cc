#include "models/haptic/force_sum.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::models::haptic {

ForceSum::ForceSum(double timeout_s) : timeout_(timeout_s) {
  if (!(timeout_s > 0) || !std::isfinite(timeout_s))
    throw std::invalid_argument("force sum: timeout must be finite and > 0");
}

void ForceSum::set(const std::string& source, const LocalModel& model, double t) { latest_[source] = {model, t}; }

void ForceSum::expire(double t) {
  for (auto it = latest_.begin(); it != latest_.end();) {
    if (t - it->second.t > timeout_) {
      it = latest_.erase(it);
      ++expired_;
    } else {
      ++it;
    }
  }
}

Eigen::Vector3d ForceSum::total(double t, const Eigen::Vector3d& x) {
  expire(t);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (auto& [name, l] : latest_) {
    l.rendered = evaluate(l.model, x);
    sum += l.rendered;
  }
  return sum;
}

bool ForceSum::covers(const std::string& source, const Eigen::Vector3d& x) const {
  const auto it = latest_.find(source);
  return it != latest_.end() && models::haptic::covers(it->second.model, x);
}

Eigen::Vector3d ForceSum::force_of(const std::string& source) const {
  const auto it = latest_.find(source);
  return it == latest_.end() ? Eigen::Vector3d::Zero() : it->second.rendered;
}

}  // namespace hcosim::models::haptic
