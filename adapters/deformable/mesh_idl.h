// Conversions from the deformable models to the DeformedMesh and
// MeshTopology topics (forces: device/haptic_idl.h).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "idl/mesh.h"
#include "models/deformable/object.h"

namespace hcosim::adapters::deformable {

// Version 1 of an object's topology.
MeshTopology mesh_topology(const std::string& mesh, int vertex_count, const std::vector<Eigen::Vector3i>& triangles);

// Fills `out` (reusing its buffers) with positions x and their vertex normals.
void fill_mesh(DeformedMesh& out, const std::string& mesh, const StepStamp& stamp, const Eigen::Matrix3Xd& x,
               const std::vector<Eigen::Vector3i>& triangles);

}  // namespace hcosim::adapters::deformable
