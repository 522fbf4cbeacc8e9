// The stylus's friction against an object, as a scene object's params
// give it (docs/haptic.md): `friction: 0.4` (static and dynamic alike) or
// `friction: {static: 0.5, dynamic: 0.3}`; 0.3 when absent, 0 frictionless.
#pragma once

#include "adapters/config.h"
#include "models/haptic/friction.h"

namespace hcosim::adapters::device {

// The highest friction coefficient any config takes: above it is a typo,
// not a material.
inline constexpr double kMaxFriction = 10;

// Throws adapters::ConfigError at FILE:LINE:COL for a coefficient outside
// [0, 10], a map with another key or without both, or a dynamic
// coefficient above the static one.
models::haptic::Friction friction_config(const Config& object);

}  // namespace hcosim::adapters::device
