// A device that plays back a recorded stylus trajectory: a CSV file with
// the header `time_s,x,y,z,buttons` (world frame, m; buttons as a bit mask),
// as `hcosim record` writes from HapticState. Times must increase. The
// device moves as recorded whatever force it is given (open loop); forces
// are still clamped and counted.
#pragma once

#include <string>
#include <vector>

#include "adapters/device/device.h"

namespace hcosim::adapters::device {

struct Sample {
  double t;
  Eigen::Vector3d x;
  std::uint32_t buttons;
};

// Throws std::runtime_error as "FILE:LINE: problem" for an unreadable file,
// a bad header, a malformed or non-finite row, or times that do not increase.
std::vector<Sample> load_trajectory(const std::string& path);

class Replay : public Device {
 public:
  Replay(const models::haptic::OmniSpec& spec, std::vector<Sample> trajectory);

  bool finished() const override { return now() > samples_.back().t + 1e-9; }

 protected:
  Frame read_frame() override;
  void write_force(const Eigen::Vector3d&) override {}

 private:
  Eigen::Vector3d at(double t, std::uint32_t* buttons) const;  // linear between samples, held past the ends

  double now() const { return samples_.front().t + double(frames()) / spec().servo_hz; }

  std::vector<Sample> samples_;
};

}  // namespace hcosim::adapters::device
