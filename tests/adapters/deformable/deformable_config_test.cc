#include "adapters/deformable/deformable_config.h"

#include <gtest/gtest.h>

#include "tests/support/doc_keys.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::deformable {
namespace {

using tests::message_of;

Config params(const std::string& text) { return Config::parse(text, "d.yaml", "params"); }

TEST(DeformableConfig, ReadsEachObjectsSpec) {
  const DeformableConfig d = deformable_config(
      params("device: right\nvisual_rate: 60\ntip_radius: 0.002\nobjects:\n"
             "  - {name: organ, size: 0.06, elements: 5, stiff_ratio: 3, map: trilinear, behavior_rate: 500,"
             " friction: 0.6, volume: 3, behavior: fem, young: 20000, poisson: 0.35, density: 1100}\n"
             "  - {name: skin, model: sheet, size: 0.1, resolution: 12, stiffness: 40, centre: [0, 0, 0.01],"
             " bending: 0.001, friction: {static: 0.5, dynamic: 0.4}}\n"
             "  - {name: dome, model: semisphere, contact_stiffness: 300}\n"),
      0.001);
  EXPECT_EQ(d.device, "right");
  EXPECT_EQ(d.visual_rate_hz, 60);
  ASSERT_EQ(d.objects.size(), 3u);
  const models::deformable::HybridSpec& h = d.objects[0].hybrid;
  EXPECT_EQ(d.objects[0].model, "hybrid");
  EXPECT_EQ(h.size, 0.06);
  EXPECT_EQ(h.elements, 5);
  EXPECT_EQ(h.stiff_ratio, 3);
  EXPECT_EQ(h.volume, 3);
  EXPECT_EQ(h.behavior_model, models::deformable::BehaviorModel::fem);
  EXPECT_EQ(h.fem.young, 20000);
  EXPECT_EQ(h.fem.poisson, 0.35);
  EXPECT_EQ(h.fem.density, 1100);
  EXPECT_EQ(deformable_config(params("objects: [{name: a}]\n"), 0.001).objects[0].hybrid.behavior_model,
            models::deformable::BehaviorModel::springs);
  EXPECT_EQ(deformable_config(params("objects: [{name: a}]\n"), 0.001).objects[0].hybrid.volume,
            models::deformable::HybridSpec{}.volume);  // volume floors by default
  EXPECT_GT(models::deformable::HybridSpec{}.volume, 0);
  const models::deformable::HybridSpec modal =
      deformable_config(params("objects: [{name: a, behavior: modal, modes: 12}]\n"), 0.001).objects[0].hybrid;
  EXPECT_EQ(modal.behavior_model, models::deformable::BehaviorModel::modal);
  EXPECT_EQ(modal.modes, 12);
  EXPECT_EQ(h.map, models::deformable::VisualMap::trilinear);
  EXPECT_DOUBLE_EQ(h.behavior.dt, 0.002);
  EXPECT_EQ(h.centre, Eigen::Vector3d(0, 0, 0.05));  // a hybrid stands on the marker by default
  EXPECT_EQ(h.friction.static_mu, 0.6);
  EXPECT_EQ(h.friction.dynamic_mu, 0.6);
  const models::deformable::SurfaceSpec& s = d.objects[1].surface;
  EXPECT_EQ(s.shape, models::deformable::Shape::sheet);
  EXPECT_EQ(s.resolution, 12);
  EXPECT_EQ(s.material.k, 40);
  EXPECT_EQ(s.centre, Eigen::Vector3d(0, 0, 0.01));
  EXPECT_EQ(s.bending, 0.001);
  EXPECT_EQ(s.friction.static_mu, 0.5);
  EXPECT_EQ(s.friction.dynamic_mu, 0.4);
  EXPECT_EQ(s.contact_stiffness, 5 * 40);  // five times its springs' by default
  EXPECT_EQ(d.objects[2].surface.contact_stiffness, 300);
  EXPECT_EQ(d.objects[2].surface.friction.dynamic_mu, 0.3);
  EXPECT_EQ(s.options.dt, 0.001);  // a surface steps with the service
  EXPECT_EQ(d.objects[2].surface.shape, models::deformable::Shape::semisphere);
  EXPECT_EQ(d.objects[2].surface.centre, Eigen::Vector3d::Zero());
  EXPECT_EQ(d.objects[2].surface.resolution, 12);  // a dome's default rings; a sheet's 21 masses per edge
  EXPECT_EQ(d.objects[2].surface.bending, models::deformable::SurfaceSpec{}.bending);  // shape memory by default
  EXPECT_GT(d.objects[2].surface.bending, 0);
  for (const ObjectConfig& o : d.objects)  // the stylus's, for every object
    EXPECT_EQ(o.model == "hybrid" ? o.hybrid.tip_radius : o.surface.tip_radius, 0.002) << o.name;
  EXPECT_EQ(deformable_config(params("objects: [{name: a}]\n"), 0.001).objects[0].hybrid.tip_radius, 0);
}

TEST(DeformableConfig, TheModelIsTheOneAsked) {
  tests::TempDir dir;
  const DeformableConfig d =
      deformable_config(params("objects:\n  - {name: a, model: sheet, resolution: 4}\n  - {name: b, elements: 3, "
                               "visual_subdivisions: 2, map: trilinear}\n"),
                        0.001);
  const auto sheet = make_object(d.objects[0], dir.path.string());
  EXPECT_NE(dynamic_cast<models::deformable::ElasticSurface*>(sheet.get()), nullptr);
  const auto hybrid = make_object(d.objects[1], dir.path.string());
  EXPECT_NE(dynamic_cast<models::deformable::Hybrid*>(hybrid.get()), nullptr);
  EXPECT_EQ(hybrid->surface().cols(), 6 * 2 * 2 + 2);
}

// A unit cube as quads, outward: an organ's mesh at its simplest.
constexpr const char* kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

TEST(DeformableConfig, AnOrgansMeshIsReadAndItsMistakesNamedWhereItIsAsked) {
  tests::TempDir dir;
  const std::string cube = dir.file("cube.obj", kCubeObj);
  const DeformableConfig d =
      deformable_config(params("objects: [{name: organ, mesh: " + cube + ", size: 0.03, elements: 4}]\n"), 0.001);
  EXPECT_EQ(d.objects[0].hybrid.shape.vertices.cols(), 8);
  EXPECT_EQ(d.objects[0].hybrid.shape.triangles.size(), 12u);
  const std::string open = dir.file("open.obj", std::string(kCubeObj).substr(0, std::string(kCubeObj).rfind("f ")));
  const std::string bad = dir.file("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
  const std::pair<std::string, std::string> cases[] = {
      {"objects: [{name: o, mesh: " + open + "}]\n", "d.yaml:1:27: hybrid: shape: mesh is not closed"},
      {"objects: [{name: o, mesh: " + bad + "}]\n", "bad.obj:3: vertex index 9 is outside 1..2"},
      {"objects: [{name: o, mesh: " + cube + ", rounding: 3}]\n", "rounding shapes the cube"},
      {"objects: [{name: o, mesh: " + cube + ", map: trilinear}]\n", "mapped by mvc or mvc_sparse"},
      {"objects: [{name: o, mesh: " + dir.path.string() + "/none.obj}]\n", "d.yaml:1:27"},
  };
  for (const auto& c : cases) {
    const std::string message = message_of([&] { deformable_config(params(c.first), 0.001); });
    EXPECT_NE(message.find(c.second), std::string::npos) << c.first << " -> " << message;
  }
}

TEST(DeformableConfig, MistakesAreNamedAtTheirPlace) {
  const auto error = [](const std::string& text) {
    return message_of<ConfigError>([&] { deformable_config(params(text), 0.001); });
  };
  EXPECT_EQ(error("device: omni\n"),
            "d.yaml:1:1: hcosim_deformable: params.objects lists no object; docs/deformable.md");
  EXPECT_EQ(error("objects: [{name: a}, {name: a, model: sheet}]\n"), "d.yaml:1:29: two objects are named 'a'");
  EXPECT_EQ(error("objects: [{name: a, model: jelly}]\n"),
            "d.yaml:1:28: 'model' must be one of hybrid, sheet, semisphere, not 'jelly'");
  // A sheet has no elements: the hybrid's keys are not a surface's.
  EXPECT_EQ(error("objects: [{name: a, model: sheet, elements: 4}]\n").rfind("d.yaml:1:35: unknown key 'elements'", 0),
            0u);
  EXPECT_EQ(error("objects: [{name: a, elements: 2}]\n"),
            "d.yaml:1:31: 'elements' must be a whole number from 3 to 100, not 2");
  EXPECT_EQ(error("objects: [{model: sheet}]\n"), "d.yaml:1:11: each object needs a name of 1 to 31 characters");
  EXPECT_EQ(error("objects: [{name: a, model: semisphere, bending: -1}]\n"),
            "d.yaml:1:49: 'bending' = -1 is outside [0, 1]");
  EXPECT_EQ(error("objects: [{name: a, volume: -1}]\n"), "d.yaml:1:29: 'volume' = -1 is outside [0, 1000]");
  EXPECT_EQ(error("objects: [{name: a, behavior: fem, poisson: 0.5}]\n"),
            "d.yaml:1:45: 'poisson' = 0.5 is outside [0, 0.49]");
  EXPECT_EQ(error("objects: [{name: a, behavior: soft}]\n").rfind("d.yaml:1:31: 'behavior'", 0), 0u);
  EXPECT_EQ(error("objects: [{name: a, modes: 8}]\n"),
            "d.yaml:1:28: modes counts the modal behavior model's modes (behavior: modal)");
  EXPECT_EQ(error("objects: [{name: a, behavior: modal, modes: 0}]\n"),
            "d.yaml:1:45: 'modes' must be a whole number from 1 to 4500, not 0");
  EXPECT_EQ(error("objects: [{name: a, friction: 11}]\n"), "d.yaml:1:31: 'friction' = 11 is outside [0, 10]");
  EXPECT_EQ(error("tip_radius: 0.008\nobjects: [{name: a, size: 0.015}]\n"),
            "d.yaml:2:27: the object must be wider than the stylus tip (tip_radius)");
  EXPECT_EQ(error("tip_radius: 0.02\nobjects: [{name: a}]\n"), "d.yaml:1:13: 'tip_radius' = 0.02 is outside [0, 0.01]");
}

// Every key the reader takes is in docs/deformable.md's table for its map,
// and every key there is one the reader takes.
TEST(DeformableConfig, EachMapsKeysAreTheDocumentedOnes) {
  const std::pair<const char*, const std::vector<std::string>*> maps[] = {{"deformable.params", &keys::kParams},
                                                                          {"deformable.hybrid", &keys::kHybrid},
                                                                          {"deformable.surface", &keys::kSurface}};
  for (const auto& [table, read] : maps)
    EXPECT_EQ(tests::documented_keys("deformable.md", table), tests::sorted(*read)) << "docs/deformable.md, " << table;
}

}  // namespace
}  // namespace hcosim::adapters::deformable
