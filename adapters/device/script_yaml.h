// Virtual-user scripts as YAML files. The format (docs/haptic.md):
//
//   start: [0, 0, 0.02]              # hand target at t = 0, world frame, m
//   actions:
//     - move_to: {to: [0, 0, 0.005], speed: 0.05}
//     - press: {depth: 0.004, speed: 0.01}      # or force: 1.5 (N); direction: [0, 0, -1]
//     - hold: {duration: 0.5}
//     - stroke: {by: [0.02, 0, 0], speed: 0.02}
//     - tap: {depth: 0.002, duration: 0.1}
//     - release: {speed: 0.02}
#pragma once

#include <string>

#include "models/haptic/virtual_user.h"

namespace hcosim::adapters::device {

// Throws hcosim::ConfigError as "FILE:LINE:COL: what" for anything it
// cannot read or that makes no sense.
models::haptic::Script load_script(const std::string& path);

}  // namespace hcosim::adapters::device
