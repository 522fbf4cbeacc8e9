#include "adapters/foxglove/bridge_config.h"

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters::foxglove {
namespace {

Config params(const std::string& text) { return Config::parse(text, "f.yaml", "params"); }

TEST(BridgeConfig, ReadsWhereItListensAndHowItDraws) {
  MarkerSpec marker;
  marker.id = 6;
  const BridgeConfig b = bridge_config(
      params("port: 0\naddress: 0.0.0.0\nclient_limit_mb: 2\njpeg_quality: 50\nscene_rate: 30\n"), marker);
  EXPECT_EQ(b.port, 0);
  EXPECT_EQ(b.address, "0.0.0.0");
  EXPECT_EQ(b.client_limit_bytes, 2000000u);
  EXPECT_EQ(b.panels.jpeg_quality, 50);
  EXPECT_EQ(b.panels.rate_hz, 30);
  EXPECT_EQ(b.panels.tag_id, 6);  // the world frame stands on the scene's marker
  const BridgeConfig d = bridge_config(params("{}"), {});
  EXPECT_EQ(d.port, 8765);
  EXPECT_EQ(d.address, "127.0.0.1");
  EXPECT_EQ(d.panels.tag_id, Options().tag_id);
}

TEST(BridgeConfig, MistakesAreNamedAtTheirPlace) {
  const auto error = [](const std::string& text) {
    return tests::message_of<ConfigError>([&] { bridge_config(params(text), {}); });
  };
  EXPECT_EQ(error("port: 70000\n"), "f.yaml:1:7: 'port' must be a whole number from 0 to 65535, not 70000");
  EXPECT_NE(error("prot: 1\n").find("f.yaml:1:1: unknown key 'prot'"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::adapters::foxglove
