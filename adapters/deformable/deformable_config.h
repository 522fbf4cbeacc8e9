// The deformable service's params (docs/deformable.md) read into the
// deformable models' specs: the hybrid model, the elastic sheet and the
// semi-sphere, one per object.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "adapters/config.h"
#include "adapters/device/device_config.h"
#include "models/deformable/elastic_surface.h"
#include "models/deformable/hybrid.h"

namespace hcosim::adapters::deformable {

// The keys of the service's params and of each kind of object, as
// docs/deformable.md's tables list them (a test holds the two to each other).
namespace keys {
inline const std::vector<std::string> kParams{"device", "visual_rate", "objects", "tip_radius"};
inline const std::vector<std::string> kHybrid{"name",
                                              "model",
                                              "centre",
                                              "size",
                                              "elements",
                                              "mesh",
                                              "stiff_ratio",
                                              "volume",
                                              "behavior",
                                              "modes",
                                              "young",
                                              "poisson",
                                              "density",
                                              "map",
                                              "keep",
                                              "behavior_rate",
                                              "visual_subdivisions",
                                              "rounding",
                                              "friction"};
inline const std::vector<std::string> kSurface{"name",       "model",     "centre",           "size",
                                               "resolution", "stiffness", "damping",          "prestretch",
                                               "bending",    "friction",  "contact_stiffness"};
}  // namespace keys

// One object: a hybrid model, or an elastic surface (sheet or semi-sphere).
struct ObjectConfig {
  std::string name;
  std::string model;  // hybrid, sheet or semisphere
  models::deformable::HybridSpec hybrid;
  models::deformable::SurfaceSpec surface;
};

struct DeformableConfig {
  std::string device = device::kDefaultDevice;  // the haptic device whose stylus touches the objects
  double visual_rate_hz = 30;                   // deformed meshes a second
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
