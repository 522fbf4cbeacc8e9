// The stylus's friction as an object's params give it: one coefficient,
// static and dynamic, the default, and located mistakes.
#include "adapters/device/friction_config.h"

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters::device {
namespace {

models::haptic::Friction read(const std::string& text) {
  return friction_config(Config::parse(text, "o.yaml", "object"));
}

TEST(FrictionConfig, OneCoefficientOrStaticAndDynamic) {
  EXPECT_EQ(read("name: a\n").static_mu, 0.3);  // the default
  EXPECT_EQ(read("name: a\n").dynamic_mu, 0.3);
  EXPECT_EQ(read("friction: 0\n").static_mu, 0);
  EXPECT_EQ(read("friction: 0.5\n").dynamic_mu, 0.5);
  const models::haptic::Friction f = read("friction: {static: 0.6, dynamic: 0.4}\n");
  EXPECT_EQ(f.static_mu, 0.6);
  EXPECT_EQ(f.dynamic_mu, 0.4);
}

TEST(FrictionConfig, MistakesAreLocated) {
  const auto error = [](const std::string& text) { return tests::message_of<ConfigError>([&] { read(text); }); };
  EXPECT_EQ(error("friction: {static: 0.2, dynamic: 0.4}\n"),
            "o.yaml:1:34: 'dynamic' friction must not exceed 'static'");
  EXPECT_EQ(error("friction: {static: 0.2}\n"), "o.yaml:1:11: 'friction' is missing required key 'dynamic'");
  EXPECT_EQ(error("friction: -1\n"), "o.yaml:1:11: 'friction' = -1 is outside [0, 10]");
  EXPECT_NE(error("friction: {static: 0.2, dynamic: 0.1, kinetic: 0}\n").find("kinetic"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::adapters::device
