#include "adapters/render/ar_idl.h"

#include <stdexcept>

#include "adapters/device/haptic_idl.h"
#include "adapters/vision/vision_idl.h"

namespace hcosim::adapters::render {

models::render::Mesh mesh(const DeformedMesh& m, const MeshTopology& t) {
  const std::string name = m.mesh().to_string();
  if (name != t.mesh().to_string() || m.topology_version() != t.topology_version())
    throw std::invalid_argument("mesh '" + name + "' version " + std::to_string(m.topology_version()) +
                                " has no matching topology");
  if (m.positions().size() != 3 * std::size_t(t.vertex_count()))
    throw std::invalid_argument("mesh '" + name + "' has " + std::to_string(m.positions().size() / 3) +
                                " vertices, its topology " + std::to_string(t.vertex_count()));
  models::render::Mesh out;
  out.vertices =
      Eigen::Map<const Eigen::Matrix3Xf>(m.positions().data(), 3, Eigen::Index(t.vertex_count())).cast<double>();
  out.triangles.assign(t.triangles().begin(), t.triangles().end());
  return out;
}

models::render::Mesh body(const RigidBodyState& s, double size) {
  const std::string shape = s.shape().to_string();
  if (shape != "cube" && shape != "sphere")
    throw std::invalid_argument("body '" + s.body().to_string() + "' has shape '" + shape + "', not cube or sphere");
  return models::render::placed(shape == "cube" ? models::render::cube(size) : models::render::sphere(size),
                                adapters::vision::from_idl(s.pose()));
}

models::render::Stylus stylus(const HapticState& s) {
  models::render::Stylus out;
  out.tip = adapters::device::from_idl(s.position());
  out.orientation = adapters::vision::from_idl(s.orientation());
  out.force = adapters::device::from_idl(s.rendered_force());
  return out;
}

}  // namespace hcosim::adapters::render
