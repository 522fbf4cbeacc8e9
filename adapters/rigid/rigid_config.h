// The rigid service's params (docs/rigid.md) read into what the rigid
// models take: the world's spec, its bodies, and how the service drives
// them (backend, the stylus's virtual coupling).
#pragma once

#include <string>
#include <vector>

#include "adapters/config.h"
#include "adapters/device/device_config.h"
#include "adapters/scene.h"
#include "models/haptic/friction.h"
#include "models/rigid/coupling.h"
#include "models/rigid/world.h"

namespace hcosim::adapters::rigid {

struct RigidConfig {
  std::string device = device::kDefaultDevice;  // the haptic device whose stylus touches the bodies
  std::string backend = "analytic";             // analytic, mujoco or crosscheck (both, MuJoCo's divergence told)
  models::rigid::WorldSpec spec;                // ground, materials, the stylus tip's radius
  models::rigid::CouplingSpec coupling;         // the stylus to each body's proxy
  int mujoco_substeps = 10;                     // MuJoCo steps per service step
  std::vector<std::string> names;               // the bodies' names (ForceFeedback.source), in file order
  std::vector<models::rigid::Body> bodies;
  std::vector<models::haptic::Friction> frictions;  // the stylus against each body, felt through its proxy
};

// `marker`: the scene's, whose friction is the plane's unless the params
// give `floor_friction`. Throws adapters::ConfigError at FILE:LINE:COL for
// an unknown key, a value out of range, a body without a unique name or
// starting inside the marker plane, or no body at all.
RigidConfig rigid_config(const Config& params, const MarkerSpec& marker = {});

// A body's `size` (half-edge or radius, m) as rigid_config reads it, for
// those that draw the body: its default when absent.
double body_size(const Config& body);

}  // namespace hcosim::adapters::rigid
