#include "adapters/render/view_config.h"

#include <gtest/gtest.h>

#include "models/rigid/body.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::render {
namespace {

Config params(const std::string& text) { return Config::parse(text, "v.yaml", "params"); }

TEST(ViewConfig, ReadsTheScenesObjectsAndTheOutputs) {
  const ViewConfig v = view_config(
      params(
          "camera: cam\ntag_id: 7\nobjects:\n  - {name: box, kind: rigid, size: 0.01}\n  - {name: ball, kind: rigid}\n"
          "  - {name: organ}\nsnapshots: [3, 1.5]\nplots: off\nstylus: false\nforce_scale: 0.05\nvideo: ''\n"),
      30);
  EXPECT_EQ(v.camera, "cam");
  EXPECT_EQ(v.tag_id, 7);
  EXPECT_EQ(v.device, "omni");
  ASSERT_EQ(v.items.size(), 3u);
  EXPECT_EQ(v.items[0].size, 0.01);
  EXPECT_EQ(v.items[1].size, models::rigid::Body().size);  // the rigid service's own default
  EXPECT_EQ(v.items[2].kind, "deformable");
  EXPECT_NE(v.items[0].colour, v.items[1].colour);
  EXPECT_EQ(v.snapshots, (std::vector<double>{1.5, 3}));  // in time order
  EXPECT_FALSE(v.plots);
  EXPECT_FALSE(v.stylus);
  EXPECT_EQ(v.force_scale, 0.05);
  EXPECT_EQ(v.video, "");
  EXPECT_EQ(v.fps, 30);  // the camera's rate: the service's
}

// The scene's marker registers the view unless the params name a tag.
TEST(ViewConfig, TheScenesMarkerRegistersItUnlessTheParamsSay) {
  MarkerSpec marker;
  marker.id = 4;
  EXPECT_EQ(view_config(params("objects: []\n"), 30, marker).tag_id, 4);
  EXPECT_EQ(view_config(params("tag_id: 2\n"), 30, marker).tag_id, 2);
  EXPECT_EQ(view_config(params("objects: []\n"), 30, {}).tag_id, 0);
}

TEST(ViewConfig, MistakesAreNamedAtTheirPlace) {
  const auto error = [](const std::string& text) {
    return tests::message_of<ConfigError>([&] { view_config(params(text), 30); });
  };
  EXPECT_EQ(error("objects: [{kind: rigid}]\n"), "v.yaml:1:11: each object needs a name");
  EXPECT_EQ(error("objects: [{name: a, kind: fluid}]\n"),
            "v.yaml:1:27: 'kind' must be one of rigid, deformable, not 'fluid'");
  EXPECT_EQ(error("snapshots: [1, -2]\n"), "v.yaml:1:16: an entry of 'snapshots', -2, is outside [0, 1e+06]");
  EXPECT_EQ(error("fsp: 30\n").rfind("v.yaml:1:1: unknown key 'fsp'; did you mean 'fps'?", 0), 0u);
}

}  // namespace
}  // namespace hcosim::adapters::render
