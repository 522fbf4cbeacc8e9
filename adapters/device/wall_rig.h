// The stiff-wall rig: the simulated Omni, held by the virtual user, presses
// into a virtual wall whose force reaches the device `delay` late, as it
// would from a model in another process. Used by the stability tests and
// `hcosim bench haptic`.
#pragma once

#include <cstdint>

#include "models/haptic/omni.h"
#include "models/haptic/wall.h"

namespace hcosim::adapters::device {

struct WallRig {
  // Without back-drive friction: it dissipates, and would hide a delayed
  // wall's buzz and what the passivity controller does about it.
  models::haptic::OmniSpec spec = [] {
    models::haptic::OmniSpec s;
    s.backdrive_friction = 0;
    return s;
  }();
  models::haptic::Hand hand;
  models::haptic::Wall wall;  // through the origin, normal +z, by default
  double delay_s = 0;         // force latency, rounded to whole servo ticks
  bool passivity = true;      // passivity observer and controller on
  double max_damping = 20;    // N s/m, the controller's cap
  double reservoir = 1e-4;    // J, the most energy the observer banks
  double press_depth = 0.01;  // m the hand's target goes behind the wall
  double speed = 0.05;        // m/s of every move
  double hold_s = 1.0;        // s held at depth
};

struct WallRun {
  double depth_m = 0;           // mean tip depth over the last half of the hold
  double peak_to_peak_m = 0;    // tip excursion over the last half of the hold
  double max_force_n = 0;       // largest force the device output
  double energy_out_j = 0;      // net work the device did on the tip over the run
  double max_energy_out_j = 0;  // largest running value of that work
  std::uint64_t saturated = 0;  // ticks the device clamped the force
  bool stable = false;          // settled: excursion under 4 encoder steps, energy out bounded
};

// Runs the rig: approach, press, hold, release. Throws std::invalid_argument
// for a negative or non-finite delay.
WallRun run_wall(const WallRig& rig);

// The tip depth at which the hand's pull balances the wall's push.
double balance_depth(const WallRig& rig);

}  // namespace hcosim::adapters::device
