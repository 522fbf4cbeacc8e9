// The deployment's scene (docs/deployment.md, "The scene"): the tag the
// rig stands on, the camera that sees it, and the objects the services
// serve. The marker is read here, once; the camera and each object are
// their services' own params and are read by those services' readers.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "adapters/config.h"

namespace hcosim::adapters {

// What an AprilTag can be: the tracker's and the AR view's params and the
// scene's marker check against these.
namespace tag {
inline const std::vector<std::string> kFamilies{"tag36h11", "tag25h9", "tag16h5", "tagStandard41h12"};
inline constexpr int kMaxId = 1000000;
inline constexpr double kMinSize = 1e-3;  // m, the black border's edge
inline constexpr double kMaxSize = 10;    // m
}  // namespace tag

namespace keys {
inline const std::vector<std::string> kScene{"marker", "camera", "objects"};
inline const std::vector<std::string> kMarker{"family", "id", "size", "friction"};
}  // namespace keys

// The tag the scene stands on. A key the file leaves out is empty here,
// and the service that would take it keeps its own default.
struct MarkerSpec {
  std::optional<std::string> family;  // the tracker's and the synthetic camera's tag family
  std::optional<int> id;              // the tag's id: the synthetic camera's, the AR view's and Foxglove's frame
  std::optional<double> size;         // m, the tag's black border's edge
  std::optional<double> friction;     // the plane's against the rigid bodies
};

struct Scene {
  bool defined = false;  // the file has a scene: services it does not need are not started
  MarkerSpec marker;
  YAML::Node camera;                // the tracker's params (a map), or null
  std::vector<YAML::Node> objects;  // maps with a unique name and kind rigid or deformable, else their service's keys
};

// Reads the scene section. Throws ConfigError at FILE:LINE:COL for an
// unknown key, a marker value out of range, or an object without a unique
// name or with a kind other than rigid or deformable.
Scene scene_config(const Config& scene);

}  // namespace hcosim::adapters
