// A simulated PHANToM Omni held by the virtual user: the tip's dynamics
// under the hand and the output force (haptic/omni.h), the encoder's
// resolution, and a velocity estimated from encoder positions as a real
// device's driver does.
#pragma once

#include "adapters/device/device.h"
#include "models/haptic/virtual_user.h"

namespace hcosim::adapters::device {

class SimulatedOmni : public Device {
 public:
  SimulatedOmni(const models::haptic::OmniSpec& spec, const models::haptic::Hand& hand, models::haptic::Script script);

  bool finished() const override { return user_.done(); }

  // Ground truth, for tests and benchmarks: the tip's true state and the
  // hand's current target.
  const models::haptic::Tip& tip() const { return tip_; }
  const Eigen::Vector3d& target() const { return target_; }
  const models::haptic::VirtualUser& user() const { return user_; }

 protected:
  Frame read_frame() override;
  void write_force(const Eigen::Vector3d& force) override;

 private:
  models::haptic::Hand hand_;
  models::haptic::VirtualUser user_;
  models::haptic::Tip tip_;
  Eigen::Vector3d target_;
  Eigen::Vector3d reported_, velocity_ = Eigen::Vector3d::Zero();
  double dt_, time_ = 0;
};

}  // namespace hcosim::adapters::device
