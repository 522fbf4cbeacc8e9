#include "render/ar_idl.h"

#include <stdexcept>

#include "device/haptic_idl.h"
#include "vision/vision_idl.h"

namespace hcosim::render {

Mesh mesh(const DeformedMesh& m, const MeshTopology& t) {
  const std::string name = m.mesh().to_string();
  if (name != t.mesh().to_string() || m.topology_version() != t.topology_version())
    throw std::invalid_argument("mesh '" + name + "' version " + std::to_string(m.topology_version()) +
                                " has no matching topology");
  if (m.positions().size() != 3 * std::size_t(t.vertex_count()))
    throw std::invalid_argument("mesh '" + name + "' has " + std::to_string(m.positions().size() / 3) +
                                " vertices, its topology " + std::to_string(t.vertex_count()));
  Mesh out;
  out.vertices = Eigen::Map<const Eigen::Matrix3Xf>(m.positions().data(), 3, Eigen::Index(t.vertex_count())).cast<double>();
  out.triangles.assign(t.triangles().begin(), t.triangles().end());
  return out;
}

Mesh body(const RigidBodyState& s, double size) {
  const std::string shape = s.shape().to_string();
  if (shape != "cube" && shape != "sphere")
    throw std::invalid_argument("body '" + s.body().to_string() + "' has shape '" + shape + "', not cube or sphere");
  return placed(shape == "cube" ? cube(size) : sphere(size), vision::from_idl(s.pose()));
}

Stylus stylus(const HapticState& s) {
  Stylus out;
  out.tip = device::from_idl(s.position());
  out.orientation = vision::from_idl(s.orientation());
  out.force = device::from_idl(s.rendered_force());
  return out;
}

}  // namespace hcosim::render
