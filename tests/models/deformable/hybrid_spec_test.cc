// The hybrid model's spec: names that parse back, checks that name the bad
// field, and the force gain's key, which every field the gain reads
// changes and no other does.
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "models/deformable/hybrid_spec.h"
#include "tests/support/shapes.h"
#include "tests/support/temp_dir.h"

namespace hcosim::models::deformable {
namespace {

TEST(HybridSpec, NamesParseBackAndAnUnknownOneListsThem) {
  for (const VisualMap m : {VisualMap::mvc, VisualMap::mvc_sparse, VisualMap::trilinear})
    EXPECT_EQ(parse_visual_map(name(m)), m);
  for (const BehaviorModel m : {BehaviorModel::springs, BehaviorModel::fem, BehaviorModel::modal})
    EXPECT_EQ(parse_behavior_model(name(m)), m);
  EXPECT_NE(tests::message_of([] { parse_visual_map("linear"); }).find("mvc, mvc_sparse, trilinear"),
            std::string::npos);
  EXPECT_NE(tests::message_of([] { parse_behavior_model("jelly"); }).find("springs, fem, modal"), std::string::npos);
}

TEST(HybridSpec, ACheckNamesTheBadField) {
  EXPECT_NO_THROW(check(HybridSpec{}));
  const std::vector<std::pair<std::string, std::function<void(HybridSpec&)>>> bad{
      {"elements", [](HybridSpec& s) { s.elements = 2; }},
      {"elements", [](HybridSpec& s) { s.elements = 101; }},
      {"size", [](HybridSpec& s) { s.size = 0; }},
      {"size", [](HybridSpec& s) { s.size = NAN; }},
      {"centre", [](HybridSpec& s) { s.centre.x() = INFINITY; }},
      {"stiff_ratio", [](HybridSpec& s) { s.stiff_ratio = 0.5; }},
      {"volume", [](HybridSpec& s) { s.volume = -1; }},
      {"volume_floor", [](HybridSpec& s) { s.volume_floor = 0; }},
      {"modes", [](HybridSpec& s) { s.modes = 0; }},
      {"visual_subdivisions", [](HybridSpec& s) { s.visual_subdivisions = 0; }},
      {"keep", [](HybridSpec& s) { s.keep = 0; }},
      {"young", [](HybridSpec& s) { s.fem.young = 1; }},
      {"poisson", [](HybridSpec& s) { s.fem.poisson = 0.5; }},
      {"density", [](HybridSpec& s) { s.fem.density = 0; }},
      {"behavior rate", [](HybridSpec& s) { s.behavior.dt = 1; }},
      {"visual_tolerance", [](HybridSpec& s) { s.visual_tolerance = s.size; }},
      {"tip_radius", [](HybridSpec& s) { s.tip_radius = 0.5 * s.size; }},
      {"mvc", [](HybridSpec& s) { s.shape = tests::loaf(), s.map = VisualMap::trilinear; }},
  };
  for (const auto& [field, spoil] : bad) {
    HybridSpec s;
    spoil(s);
    const std::string what = tests::message_of<std::invalid_argument>([&] { check(s); });
    EXPECT_EQ(what.rfind("hybrid: ", 0), 0u) << what;
    EXPECT_NE(what.find(field), std::string::npos) << field << ": " << what;
  }
}

// A gain kept under one key is used for every spec with that key: any
// field force_gain reads must change it, and the fields it does not read
// must not (a moved or touched object keeps its gain).
TEST(HybridSpec, TheGainKeyChangesWithEveryFieldTheGainReadsAndNoOther) {
  const std::vector<double> base = gain_key(HybridSpec{});
  EXPECT_EQ(base.front(), kForceGainVersion);
  const std::vector<std::pair<std::string, std::function<void(HybridSpec&)>>> read{
      {"elements", [](HybridSpec& s) { s.elements = 11; }},
      {"size", [](HybridSpec& s) { s.size = 0.05; }},
      {"shape", [](HybridSpec& s) { s.shape = tests::loaf(); }},
      {"chain.stiffness", [](HybridSpec& s) { s.chain.stiffness *= 2; }},
      {"chain.stretch", [](HybridSpec& s) { s.chain.stretch *= 2; }},
      {"chain.compress", [](HybridSpec& s) { s.chain.compress *= 2; }},
      {"chain.shear", [](HybridSpec& s) { s.chain.shear *= 2; }},
      {"relax_rate", [](HybridSpec& s) { s.relax_rate *= 2; }},
      {"limit_stiffness", [](HybridSpec& s) { s.limit_stiffness *= 2; }},
      {"material.mass", [](HybridSpec& s) { s.material.mass *= 2; }},
      {"material.k", [](HybridSpec& s) { s.material.k *= 2; }},
      {"material.b", [](HybridSpec& s) { s.material.b *= 2; }},
      {"material.drag", [](HybridSpec& s) { s.material.drag *= 2; }},
      {"stiff_ratio", [](HybridSpec& s) { s.stiff_ratio = 4; }},
      {"volume", [](HybridSpec& s) { s.volume = 5; }},
      {"volume_floor", [](HybridSpec& s) { s.volume_floor = 0.4; }},
      {"behavior_model", [](HybridSpec& s) { s.behavior_model = BehaviorModel::fem; }},
      {"fem.young", [](HybridSpec& s) { s.fem.young *= 2; }},
      {"fem.poisson", [](HybridSpec& s) { s.fem.poisson = 0.45; }},
      {"fem.density", [](HybridSpec& s) { s.fem.density *= 2; }},
      {"fem.alpha", [](HybridSpec& s) { s.fem.alpha *= 2; }},
      {"fem.beta", [](HybridSpec& s) { s.fem.beta = 1e-3; }},
      {"modes", [](HybridSpec& s) { s.modes = 8; }},
      {"visual_subdivisions", [](HybridSpec& s) { s.visual_subdivisions = 20; }},
      {"visual_exponent", [](HybridSpec& s) { s.visual_exponent = 4; }},
      {"map", [](HybridSpec& s) { s.map = VisualMap::mvc; }},
      {"keep", [](HybridSpec& s) { s.keep = 0.99; }},
  };
  for (const auto& [field, change] : read) {
    HybridSpec s;
    change(s);
    EXPECT_NE(gain_key(s), base) << field;
  }
  const std::vector<std::pair<std::string, std::function<void(HybridSpec&)>>> unread{
      {"centre", [](HybridSpec& s) { s.centre.x() += 0.2; }},
      {"behavior", [](HybridSpec& s) { s.behavior.dt = 2e-3, s.behavior.threshold = 1e-6; }},
      {"visual_tolerance", [](HybridSpec& s) { s.visual_tolerance = 1e-4; }},
      {"friction",
       [](HybridSpec& s) {
         s.friction = {0.6, 0.5};
       }},
      {"tip_radius", [](HybridSpec& s) { s.tip_radius = 0.002; }},
  };
  for (const auto& [field, change] : unread) {
    HybridSpec s;
    change(s);
    EXPECT_EQ(gain_key(s), base) << field;
  }
}

TEST(HybridSpec, TheStiffSideIsPastTheCentreAlongXAndOnlyWithARatio) {
  HybridSpec s;
  const Eigen::Vector3d right = s.centre + Eigen::Vector3d(0.01, 0, 0), left = s.centre - Eigen::Vector3d(0.01, 0, 0);
  EXPECT_FALSE(stiff_side(s, right));
  s.stiff_ratio = 4;
  EXPECT_TRUE(stiff_side(s, right));
  EXPECT_FALSE(stiff_side(s, left));
  EXPECT_FALSE(stiff_side(s, s.centre));
}

}  // namespace
}  // namespace hcosim::models::deformable
