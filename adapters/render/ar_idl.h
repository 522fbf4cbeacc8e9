// Conversions from the topics the AR view subscribes to into what it
// draws (render::View parts).
#pragma once

#include <string>

#include "hcosim/idl/haptic.h"
#include "hcosim/idl/mesh.h"
#include "hcosim/idl/rigid.h"
#include "render/view.h"

namespace hcosim::render {

// An object's deformed mesh with the topology it indexes. Throws
// std::invalid_argument when they do not match (another mesh or version,
// another vertex count).
Mesh mesh(const DeformedMesh& m, const MeshTopology& t);

// A rigid body at its pose: a cube of half-edge `size` or a sphere of
// radius `size` (m), as the rigid service's `bodies` give them. Throws
// std::invalid_argument for another shape.
Mesh body(const RigidBodyState& s, double size);

// The stylus of a device state: its tip, orientation and rendered force.
Stylus stylus(const HapticState& s);

}  // namespace hcosim::render
