#include "adapters/rigid/rigid_config.h"

#include "adapters/device/friction_config.h"

namespace hcosim::adapters::rigid {
namespace {

models::rigid::Material material(const Config& p, const std::string& prefix, models::rigid::Material m) {
  m.restitution = p.number(prefix + "restitution", m.restitution, 0, 1);
  m.friction = p.number(prefix + "friction", m.friction, 0, device::kMaxFriction);
  return m;
}

models::rigid::Body body(const Config& o, bool ground) {
  o.allow_only({"name", "shape", "size", "mass", "centre", "velocity", "angular_velocity", "friction"});
  models::rigid::Body b;
  b.shape = models::rigid::parse_shape(o.text("shape", "sphere", {"sphere", "cube"}));
  b.size = body_size(o);
  b.mass = o.number("mass", b.mass, 1e-3, 100);
  const auto c = o.vec3("centre", {0, 0, b.size});
  const auto v = o.vec3("velocity", {0, 0, 0});
  const auto w = o.vec3("angular_velocity", {0, 0, 0});
  b.x = {c[0], c[1], c[2]};
  b.v = {v[0], v[1], v[2]};
  b.w = {w[0], w[1], w[2]};
  if (b.x.norm() > 2) o.fail("centre", "a body more than 2 m from the marker is outside any rig");
  // A cube's lowest point is its centre minus size (it starts axis-aligned).
  if (ground && b.x.z() < b.size - 1e-9)
    o.fail("centre", "centre z must be at least size: the body would start inside the marker plane (ground: on)");
  return b;
}

}  // namespace

double body_size(const Config& o) { return o.number("size", models::rigid::Body().size, 1e-3, 1); }

RigidConfig rigid_config(const Config& p, const MarkerSpec& marker) {
  p.allow_only({"device", "backend", "bodies", "ground", "pair_restitution", "pair_friction", "floor_restitution",
                "floor_friction", "tip_radius", "stiffness", "damping", "max_force", "mujoco_substeps"});
  RigidConfig r;
  r.device = p.string("device", r.device);
  r.backend = p.text("backend", r.backend, {"analytic", "mujoco", "crosscheck"});
  r.spec.ground = p.on("ground", r.spec.ground);
  r.spec.pair = material(p, "pair_", r.spec.pair);
  models::rigid::Material floor = r.spec.floor;
  floor.friction = marker.friction.value_or(floor.friction);
  r.spec.floor = material(p, "floor_", floor);
  // A point unless told (the device's, by hcosim up).
  r.spec.tip_radius = p.number("tip_radius", 0, 0, device::kMaxTipRadius);
  r.coupling.stiffness = p.number("stiffness", r.coupling.stiffness, 1, 1e4);
  r.coupling.damping = p.number("damping", r.coupling.damping, 0, 100);
  r.coupling.max_force = p.number("max_force", r.coupling.max_force, 0.1, 100);
  r.mujoco_substeps = p.whole("mujoco_substeps", r.mujoco_substeps, 1, 100);
  for (const Config& o : p.list("bodies")) {
    const std::string name = o.string("name", "");
    if (name.empty() || name.size() > 31) o.fail("name", "each body needs a name of 1 to 31 characters");
    for (const std::string& n : r.names)
      if (n == name) o.fail("name", "two bodies are named '" + name + "'");
    r.names.push_back(name);
    r.bodies.push_back(body(o, r.spec.ground));
    r.frictions.push_back(device::friction_config(o));
  }
  if (r.bodies.empty()) p.fail("bodies", "hcosim_rigid: params.bodies lists no body; docs/rigid.md");
  return r;
}

}  // namespace hcosim::adapters::rigid
