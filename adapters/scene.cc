#include "adapters/scene.h"

#include <set>

#include "adapters/device/friction_config.h"

namespace hcosim::adapters {

namespace {

MarkerSpec marker_config(const Config& m) {
  m.allow_only(keys::kMarker);
  MarkerSpec out;
  if (m.has("family")) out.family = m.text("family", "", tag::kFamilies);
  if (m.has("id")) out.id = m.whole("id", 0, 0, tag::kMaxId);
  if (m.has("size")) out.size = m.number("size", 0, tag::kMinSize, tag::kMaxSize);
  if (m.has("friction")) out.friction = m.number("friction", 0, 0, device::kMaxFriction);
  return out;
}

}  // namespace

Scene scene_config(const Config& c) {
  if (!c.node().IsMap()) c.fail("", "'scene' must be a map of marker, camera and objects");
  c.allow_only(keys::kScene);
  Scene scene;
  scene.defined = true;
  if (c.has("marker")) {
    if (!c.node()["marker"].IsMap()) c.fail("marker", "'marker' must be a map");
    scene.marker = marker_config(c.map("marker"));
  }
  if (c.has("camera")) {
    if (!c.node()["camera"].IsMap())
      c.fail("camera", "'camera' must be a map of the tracker's params (docs/tracking.md)");
    scene.camera = c.map("camera").node();
  }
  std::set<std::string> names;
  for (const Config& o : c.list("objects")) {
    o.require({"name", "kind"}, "scene object");
    const std::string name = o.string("name", "");
    const std::string kind = o.string("kind", "");
    if (kind != "rigid" && kind != "deformable")
      o.fail("kind", "scene object kind must be rigid or deformable, not '" + kind + "'");
    if (!names.insert(name).second) o.fail("name", "scene object '" + name + "' is defined twice");
    scene.objects.push_back(o.node());
  }
  return scene;
}

}  // namespace hcosim::adapters
