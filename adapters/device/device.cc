#include "adapters/device/device.h"

namespace hcosim::adapters::device {

Device::Device(const models::haptic::OmniSpec& spec) : spec_(spec) { models::haptic::check(spec_); }

Eigen::Vector3d Device::end_frame(const Eigen::Vector3d& force) {
  bool saturated = false;
  const Eigen::Vector3d out = models::haptic::clamp_force(spec_, force, &saturated);
  ++frames_;
  saturated_ += saturated;
  over_continuous_ += out.norm() > spec_.continuous_force;
  write_force(out);
  return out;
}

}  // namespace hcosim::adapters::device
