#include "adapters/device/simulated_omni.h"

#include <cmath>

namespace hcosim::adapters::device {

namespace {
constexpr double kVelocityCutoffHz = 50;  // first-order filter on encoder differences
}

SimulatedOmni::SimulatedOmni(const models::haptic::OmniSpec& spec, const models::haptic::Hand& hand,
                             models::haptic::Script script)
    : Device(spec), hand_(hand), user_(std::move(script), 1 / spec.servo_hz), dt_(1 / spec.servo_hz) {
  tip_.x = target_ = user_.script().start;
  reported_ = models::haptic::quantize(spec, tip_.x);
}

Frame SimulatedOmni::read_frame() {
  Frame f;
  f.time_s = time_;
  f.position = reported_;
  f.velocity = velocity_;
  f.buttons = user_.buttons();
  return f;
}

void SimulatedOmni::write_force(const Eigen::Vector3d& force) {
  target_ = user_.next(force);
  models::haptic::step_tip(spec(), hand_, target_, force, dt_, tip_);
  time_ += dt_;
  const Eigen::Vector3d next = models::haptic::quantize(spec(), tip_.x);
  const double a = 1 - std::exp(-2 * M_PI * kVelocityCutoffHz * dt_);
  velocity_ += a * ((next - reported_) / dt_ - velocity_);
  reported_ = next;
}

}  // namespace hcosim::adapters::device
