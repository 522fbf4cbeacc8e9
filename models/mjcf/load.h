// MuJoCo 2.2.2 models from MJCF text held in memory, through its virtual
// file system: the baselines build their scenes as text, never as files.
#pragma once

#include <string>

#include <mujoco/mujoco.h>

namespace hcosim::models::mjcf {

// Loads `xml` into *model and allocates its *data. On failure throws
// std::runtime_error starting with `who` and carrying MuJoCo's message,
// and leaves nothing allocated.
void load(const std::string& who, const std::string& xml, mjModel*& model, mjData*& data);

}  // namespace hcosim::models::mjcf
