#include "adapters/render/view_config.h"

#include <algorithm>

#include "adapters/rigid/rigid_config.h"
#include "models/render/view.h"

namespace hcosim::adapters::render {

ViewConfig view_config(const Config& p, double rate_hz, const MarkerSpec& marker) {
  p.allow_only(
      {"camera", "tag_id", "device", "objects", "video", "snapshots", "plots", "force_scale", "stylus", "fps"});
  ViewConfig v;
  v.camera = p.string("camera", v.camera);
  v.tag_id = p.whole("tag_id", marker.id.value_or(v.tag_id), 0, tag::kMaxId);
  v.device = p.string("device", v.device);
  for (const Config& o : p.list("objects")) {
    ViewItem it;
    it.name = o.string("name", "");
    if (it.name.empty()) o.fail("name", "each object needs a name");
    it.kind = o.text("kind", "deformable", {"rigid", "deformable"});
    if (it.kind == "rigid") it.size = rigid::body_size(o);
    it.colour = models::render::object_colour(v.items.size());
    v.items.push_back(it);
  }
  v.snapshots = p.numbers("snapshots", 0, 1e6);
  std::sort(v.snapshots.begin(), v.snapshots.end());
  v.plots = p.on("plots", v.plots);
  v.stylus = p.on("stylus", v.stylus);
  v.force_scale = p.number("force_scale", models::render::View().force_scale, 0, 1);
  v.video = p.string("video", v.video);
  // The video's frame rate is the camera's: the service's own rate when it
  // runs at the camera's, as it should.
  v.fps = p.number("fps", rate_hz, 1, 1000);
  return v;
}

}  // namespace hcosim::adapters::render
