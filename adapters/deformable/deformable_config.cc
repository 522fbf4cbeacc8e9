#include "adapters/deformable/deformable_config.h"

#include "adapters/deformable/map_cache.h"
#include "adapters/device/friction_config.h"

namespace hcosim::adapters::deformable {
namespace {

namespace limits = models::deformable::limits;

// A key within the range the model itself accepts (models/deformable/limits.h).
double number(const Config& o, const std::string& key, double fallback, models::deformable::Range r) {
  return o.number(key, fallback, r.lo, r.hi);
}
int whole(const Config& o, const std::string& key, int fallback, models::deformable::Range r) {
  return o.whole(key, fallback, int(r.lo), int(r.hi));
}

ObjectConfig object(const Config& o, double servo_dt, double tip_radius) {
  ObjectConfig c;
  c.name = o.string("name", "");
  if (c.name.empty() || c.name.size() > 31) o.fail("name", "each object needs a name of 1 to 31 characters");
  c.model = o.text("model", "hybrid", {"hybrid", "sheet", "semisphere"});
  const auto centre = o.vec3("centre", {0, 0, c.model == "hybrid" ? 0.05 : 0});
  if (c.model == "hybrid") {
    o.allow_only(keys::kHybrid);
    models::deformable::HybridSpec& s = c.hybrid;
    s.centre = {centre[0], centre[1], centre[2]};
    s.size = number(o, "size", s.size, limits::kSize);
    s.elements = whole(o, "elements", s.elements, limits::kElements);
    s.stiff_ratio = number(o, "stiff_ratio", s.stiff_ratio, limits::kStiffRatio);
    s.volume = number(o, "volume", s.volume, limits::kVolume);
    s.behavior_model =
        models::deformable::parse_behavior_model(o.text("behavior", "springs", {"springs", "fem", "modal"}));
    s.fem.young = number(o, "young", s.fem.young, limits::kYoung);
    s.fem.poisson = number(o, "poisson", s.fem.poisson, limits::kPoisson);
    s.fem.density = number(o, "density", s.fem.density, limits::kDensity);
    s.modes = o.whole("modes", s.modes, 1, models::fem::Modal::kMaxDofs);
    if (o.has("modes") && s.behavior_model != models::deformable::BehaviorModel::modal)
      o.fail("modes", "modes counts the modal behavior model's modes (behavior: modal)");
    s.map = models::deformable::parse_visual_map(o.text("map", "mvc_sparse", {"mvc", "mvc_sparse", "trilinear"}));
    s.keep = number(o, "keep", s.keep, limits::kKeep);
    s.behavior.dt = 1 / number(o, "behavior_rate", 1 / s.behavior.dt, limits::kBehaviorRate);
    s.visual_subdivisions = whole(o, "visual_subdivisions", s.visual_subdivisions, limits::kVisualSubdivisions);
    s.visual_exponent = number(o, "rounding", s.visual_exponent, limits::kVisualExponent);
    s.friction = device::friction_config(o);
    s.tip_radius = tip_radius;
    if (tip_radius >= 0.5 * s.size) o.fail("size", "the object must be wider than the stylus tip (tip_radius)");
    if (const std::string mesh = o.path("mesh"); !mesh.empty()) {
      for (const char* cube_only : {"rounding", "visual_subdivisions"})
        if (o.has(cube_only)) o.fail(cube_only, std::string(cube_only) + " shapes the cube; a mesh is drawn as it is");
      // An organ: the OBJ's shape, checked here so that a bad file is named
      // with the line that asks for it.
      try {
        s.shape = models::massspring::read_obj(mesh);
        models::deformable::hybrid_masses(s);
      } catch (const std::exception& e) {
        o.fail("mesh", e.what());
      }
    }
    return c;
  }
  o.allow_only(keys::kSurface);
  models::deformable::SurfaceSpec& s = c.surface;
  s.shape = c.model == "sheet" ? models::deformable::Shape::sheet : models::deformable::Shape::semisphere;
  s.centre = {centre[0], centre[1], centre[2]};
  s.size = number(o, "size", s.size, limits::kSize);
  // A dome's rings hold 4 x resolution masses at its base: 12 keeps the
  // default scene's dome at the sheet's cost per tick with its hinges.
  s.resolution = whole(o, "resolution", s.shape == models::deformable::Shape::sheet ? 21 : 12, limits::kResolution);
  s.material.k = number(o, "stiffness", s.material.k, limits::kSpringStiffness);
  s.material.b = number(o, "damping", s.material.b, limits::kSpringDamping);
  s.prestretch = number(o, "prestretch", s.prestretch, limits::kPrestretch);
  s.bending = number(o, "bending", s.bending, limits::kBending);
  s.friction = device::friction_config(o);
  s.contact_stiffness = number(o, "contact_stiffness", 5 * s.material.k, limits::kContactStiffness);
  s.options.dt = servo_dt;
  s.tip_radius = tip_radius;
  if (tip_radius >= 0.5 * s.size) o.fail("size", "the object must be wider than the stylus tip (tip_radius)");
  return c;
}

}  // namespace

DeformableConfig deformable_config(const Config& p, double servo_dt) {
  p.allow_only(keys::kParams);
  DeformableConfig d;
  d.device = p.string("device", d.device);
  d.visual_rate_hz = p.number("visual_rate", d.visual_rate_hz, 1, 240);
  const double tip_radius = p.number("tip_radius", 0, 0, device::kMaxTipRadius);
  for (const Config& o : p.list("objects")) {
    ObjectConfig c = object(o, servo_dt, tip_radius);
    for (const ObjectConfig& other : d.objects)
      if (other.name == c.name) o.fail("name", "two objects are named '" + c.name + "'");
    d.objects.push_back(std::move(c));
  }
  if (d.objects.empty()) p.fail("objects", "hcosim_deformable: params.objects lists no object; docs/deformable.md");
  return d;
}

std::unique_ptr<models::deformable::Object> make_object(const ObjectConfig& o, const std::string& cache) {
  if (o.model == "hybrid")
    return std::make_unique<models::deformable::Hybrid>(o.hybrid, map_cache(cache, o.hybrid), gain_cache(cache));
  return std::make_unique<models::deformable::ElasticSurface>(o.surface);
}

}  // namespace hcosim::adapters::deformable
