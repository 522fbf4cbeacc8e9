// The haptic device service's params (docs/haptic.md) read into its
// device backend (the simulated Omni with its virtual user, or a replayed
// trajectory) and the parameters of its servo loop.
#pragma once

#include <memory>
#include <string>

#include "adapters/config.h"
#include "adapters/device/device.h"
#include "models/haptic/omni.h"
#include "models/haptic/virtual_user.h"

namespace hcosim::adapters::device {

// The device a deployment's rigid and deformable services answer, and its
// AR view draws, unless their params name another (their `device`).
inline constexpr const char* kDefaultDevice = "omni";

// m: the largest stylus tip any config takes (a tool tip, not a probe).
inline constexpr double kMaxTipRadius = 0.01;

struct DeviceConfig {
  bool replay = false;            // device: replay (a trajectory) or simulated (a virtual user)
  std::string source;             // the trajectory (CSV) or the virtual-user script (YAML)
  models::haptic::OmniSpec spec;  // its workspace centre and servo rate
  models::haptic::Hand hand;      // the virtual user's hand
  bool passivity = true;          // the passivity controller on the rendered force
  double max_damping = 20;        // N s/m, the passivity controller's most
  double reservoir = 1e-4;        // J it lets a source store before damping
  double source_timeout = 0.05;   // s after which a silent source drops out of the sum
  double answer_wait = 0;         // s a real-time tick waits for its answers
  std::string report;             // where to write the run's report (JSON), "" none
  // m: the stylus tip's radius, 0 a point. hcosim up gives it to the
  // services that serve this device's contacts (their `tip_radius`).
  double tip_radius = 0;
};

// `servo_hz`: the service's rate. Throws adapters::ConfigError at
// FILE:LINE:COL for an unknown key, a value out of range, or no source.
DeviceConfig device_config(const Config& params, double servo_hz);

// The backend the config names, its source read (scripts and
// trajectories throw their own located errors).
std::unique_ptr<Device> make_device(const DeviceConfig& c);

// Share of a tick a real-time tick waits for its answers by default; the
// rest renders and outputs.
inline constexpr double kAnswerShare = 0.8;

}  // namespace hcosim::adapters::device
