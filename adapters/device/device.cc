#include "device/device.h"

namespace hcosim::device {

Device::Device(const haptic::OmniSpec& spec) : spec_(spec) { haptic::check(spec_); }

Eigen::Vector3d Device::end_frame(const Eigen::Vector3d& force) {
  bool saturated = false;
  const Eigen::Vector3d out = haptic::clamp_force(spec_, force, &saturated);
  ++frames_;
  saturated_ += saturated;
  over_continuous_ += out.norm() > spec_.continuous_force;
  write_force(out);
  return out;
}

}  // namespace hcosim::device
