// The deformable service's params (docs/deformable.md) read into the
// deformable models' specs: the hybrid model, the elastic sheet and the
// semi-sphere, one per object.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "adapters/config.h"
#include "models/deformable/elastic_surface.h"
#include "models/deformable/hybrid.h"

namespace hcosim::adapters::deformable {

// One object: a hybrid model, or an elastic surface (sheet or semi-sphere).
struct ObjectConfig {
  std::string name;
  std::string model;  // hybrid, sheet or semisphere
  models::deformable::HybridSpec hybrid;
  models::deformable::SurfaceSpec surface;
};

struct DeformableConfig {
  std::string device = "omni";  // the haptic device whose stylus touches the objects
  double visual_rate_hz = 30;   // deformed meshes a second
  std::vector<ObjectConfig> objects;
};

// `servo_dt`: the service's step, s, which the elastic surfaces step by.
// Throws adapters::ConfigError at FILE:LINE:COL for an unknown key, a value
// out of range, an object without a unique name, or no object at all.
DeformableConfig deformable_config(const Config& params, double servo_dt);

// The object's model; a hybrid's visual map is read from (or built and
// kept in) the folder `cache` (map_cache.h).
std::unique_ptr<models::deformable::Object> make_object(const ObjectConfig& o, const std::string& cache);

}  // namespace hcosim::adapters::deformable
