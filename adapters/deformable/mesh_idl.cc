#include "adapters/deformable/mesh_idl.h"

#include "models/deformable/surface.h"

namespace hcosim::adapters::deformable {

MeshTopology mesh_topology(const std::string& mesh, int vertex_count, const std::vector<Eigen::Vector3i>& triangles) {
  MeshTopology t;
  t.mesh(mesh);
  t.topology_version(1);
  t.vertex_count(std::uint32_t(vertex_count));
  t.triangles().reserve(3 * triangles.size());
  for (const Eigen::Vector3i& f : triangles)
    for (int i = 0; i < 3; ++i) t.triangles().push_back(std::uint32_t(f[i]));
  return t;
}

void fill_mesh(DeformedMesh& out, const std::string& mesh, const StepStamp& stamp, const Eigen::Matrix3Xd& x,
               const std::vector<Eigen::Vector3i>& triangles) {
  out.mesh(mesh);
  out.stamp(stamp);
  out.topology_version(1);
  const Eigen::Matrix3Xd n = models::deformable::vertex_normals(x, triangles);
  auto& p = out.positions();
  auto& q = out.normals();
  p.resize(3 * x.cols()), q.resize(3 * x.cols());
  Eigen::Map<Eigen::Matrix3Xf>(p.data(), 3, x.cols()) = x.cast<float>();
  Eigen::Map<Eigen::Matrix3Xf>(q.data(), 3, x.cols()) = n.cast<float>();
}

}  // namespace hcosim::adapters::deformable
