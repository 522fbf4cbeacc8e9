// Conversions from the deformable models to the ForceFeedback,
// DeformedMesh and MeshTopology topics.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "deformable/object.h"
#include "hcosim/idl/haptic.h"
#include "hcosim/idl/mesh.h"

namespace hcosim::deformable {

// The answer of object `source` to HapticState `seq` of `device`.
ForceFeedback force_feedback(const std::string& source, const std::string& device, std::uint64_t seq,
                             const StepStamp& stamp, const Touch& touch);

// Version 1 of an object's topology.
MeshTopology mesh_topology(const std::string& mesh, int vertex_count, const std::vector<Eigen::Vector3i>& triangles);

// Fills `out` (reusing its buffers) with positions x and their vertex normals.
void fill_mesh(DeformedMesh& out, const std::string& mesh, const StepStamp& stamp, const Eigen::Matrix3Xd& x,
               const std::vector<Eigen::Vector3i>& triangles);

}  // namespace hcosim::deformable
