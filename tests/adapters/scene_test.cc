#include "adapters/scene.h"

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters {
namespace {

using tests::message_of;

Scene scene(const std::string& text) { return scene_config(Config::parse(text, "s.yaml", "a scene")); }

TEST(Scene, ReadsTheMarkerTypedAndKeepsWhatItLeavesOutEmpty) {
  const Scene s = scene("marker: {family: tag16h5, id: 3, size: 0.03, friction: 0.8}\n");
  EXPECT_TRUE(s.defined);
  EXPECT_EQ(s.marker.family, "tag16h5");
  EXPECT_EQ(s.marker.id, 3);
  EXPECT_EQ(s.marker.size, 0.03);
  EXPECT_EQ(s.marker.friction, 0.8);
  const Scene part = scene("marker: {id: 2}\n");
  EXPECT_EQ(part.marker.id, 2);
  EXPECT_FALSE(part.marker.family.has_value());
  EXPECT_FALSE(part.marker.size.has_value());
  EXPECT_FALSE(part.marker.friction.has_value());
  EXPECT_FALSE(scene("objects: []\n").marker.id.has_value());
}

TEST(Scene, KeepsTheCameraAndTheObjectsInFileOrder) {
  const Scene s = scene(
      "camera: {source: synthetic, width: 320}\n"
      "objects:\n  - {name: b, kind: rigid, size: 0.02}\n  - {name: a, kind: deformable, model: hybrid}\n");
  ASSERT_TRUE(s.camera.IsMap());
  EXPECT_EQ(s.camera["width"].as<int>(), 320);
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0]["name"].Scalar(), "b");
  EXPECT_EQ(s.objects[1]["kind"].Scalar(), "deformable");
}

// Each mistake is named at its place, with the marker's own key and range.
TEST(Scene, MistakesAreNamedAtTheirPlace) {
  const auto error = [](const std::string& text) { return message_of<ConfigError>([&] { scene(text); }); };
  EXPECT_EQ(error("marker: {friction: -2}\n"), "s.yaml:1:20: 'friction' = -2 is outside [0, 10]");
  EXPECT_EQ(error("marker: {size: 20}\n"), "s.yaml:1:16: 'size' = 20 is outside [0.001, 10]");
  EXPECT_EQ(error("marker: {id: -1}\n"), "s.yaml:1:14: 'id' must be a whole number from 0 to 1000000, not -1");
  EXPECT_NE(error("marker: {family: tag99}\n").find("s.yaml:1:18: "), std::string::npos);
  EXPECT_NE(error("marker: {colour: red}\n").find("s.yaml:1:10: unknown key 'colour'"), std::string::npos);
  EXPECT_EQ(error("marker: 3\n"), "s.yaml:1:9: 'marker' must be a map");
  EXPECT_EQ(error("objects:\n  - {name: a, kind: fluid}\n"),
            "s.yaml:2:21: scene object kind must be rigid or deformable, not 'fluid'");
  EXPECT_EQ(error("objects:\n  - {name: a, kind: rigid}\n  - {name: a, kind: rigid}\n"),
            "s.yaml:3:12: scene object 'a' is defined twice");
}

}  // namespace
}  // namespace hcosim::adapters
