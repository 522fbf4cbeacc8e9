// Conversions from the rigid models to the RigidBodyState and
// RigidDivergence topics (forces: device/haptic_idl.h).
#pragma once

#include <string>

#include "hcosim/idl/rigid.h"
#include "rigid/body.h"

namespace hcosim::rigid {

// Body b of the deployment's object `name`, as computed by `backend`
// ("analytic" or "mujoco").
RigidBodyState body_state(const std::string& name, const StepStamp& stamp, const Body& b, const char* backend);

// How far MuJoCo's body m has drifted from the analytic body a.
RigidDivergence divergence(const std::string& name, const StepStamp& stamp, const Body& a, const Body& m);

}  // namespace hcosim::rigid
