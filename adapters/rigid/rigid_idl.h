// Conversions from the rigid models to the RigidBodyState and
// RigidDivergence topics (forces: device/haptic_idl.h).
#pragma once

#include <string>

#include "idl/rigid.h"
#include "models/rigid/body.h"

namespace hcosim::adapters::rigid {

// Body b of the deployment's object `name`, as computed by `backend`
// ("analytic" or "mujoco").
RigidBodyState body_state(const std::string& name, const StepStamp& stamp, const models::rigid::Body& b,
                          const char* backend);

// How far MuJoCo's body m has drifted from the analytic body a.
RigidDivergence divergence(const std::string& name, const StepStamp& stamp, const models::rigid::Body& a,
                           const models::rigid::Body& m);

}  // namespace hcosim::adapters::rigid
