// Conversions from the topics the AR view subscribes to into what it
// draws (models::render::View parts).
#pragma once

#include <string>

#include "idl/haptic.h"
#include "idl/mesh.h"
#include "idl/rigid.h"
#include "models/render/view.h"

namespace hcosim::adapters::render {

// An object's deformed mesh with the topology it indexes. Throws
// std::invalid_argument when they do not match (another mesh or version,
// another vertex count).
models::render::Mesh mesh(const DeformedMesh& m, const MeshTopology& t);

// A rigid body at its pose: a cube of half-edge `size` or a sphere of
// radius `size` (m), as the rigid service's `bodies` give them. Throws
// std::invalid_argument for another shape.
models::render::Mesh body(const RigidBodyState& s, double size);

// The stylus of a device state: its tip, orientation and rendered force.
models::render::Stylus stylus(const HapticState& s);

}  // namespace hcosim::adapters::render
