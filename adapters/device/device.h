// The haptic device interface every backend implements, shaped like an
// OpenHaptics servo callback: once per tick, begin_frame() reads the
// stylus (hdBeginFrame, hdGetDoublev(HD_CURRENT_POSITION), ...) and
// end_frame() sets the force (hdSetDoublev(HD_CURRENT_FORCE), hdEndFrame).
// An OpenHaptics or CHAI3D adapter implements read_frame() and
// write_force() with those calls and nothing in services changes; this
// header needs no vendor SDK.
#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "models/haptic/omni.h"

namespace hcosim::adapters::device {

struct Frame {
  double time_s = 0;                                                // device clock, s since start
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // stylus tip (HIP), world frame, m
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();               // world frame, m/s
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // stylus to world
  std::uint32_t buttons = 0;                                        // bit i: button i pressed
};

class Device {
 public:
  explicit Device(const models::haptic::OmniSpec& spec);
  virtual ~Device() = default;
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // The stylus at the start of this servo tick.
  Frame begin_frame() { return read_frame(); }

  // Outputs `force` (world frame, N) until the next tick, clamped to
  // spec().max_force; returns what was output. A clamped or non-finite
  // command counts in saturated().
  Eigen::Vector3d end_frame(const Eigen::Vector3d& force);

  // True once a replay or script has nothing more to play.
  virtual bool finished() const { return false; }

  const models::haptic::OmniSpec& spec() const { return spec_; }
  std::uint64_t frames() const { return frames_; }
  std::uint64_t saturated() const { return saturated_; }
  std::uint64_t over_continuous() const { return over_continuous_; }  // ticks above the continuous force

 protected:
  virtual Frame read_frame() = 0;
  virtual void write_force(const Eigen::Vector3d& force) = 0;

 private:
  models::haptic::OmniSpec spec_;
  std::uint64_t frames_ = 0, saturated_ = 0, over_continuous_ = 0;
};

}  // namespace hcosim::adapters::device
