#include "adapters/device/device_config.h"

#include <gtest/gtest.h>

#include "adapters/device/replay.h"
#include "adapters/device/simulated_omni.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::device {
namespace {

using tests::message_of;

TEST(DeviceConfig, ReadsTheBackendAndTheLoop) {
  tests::TempDir dir;
  dir.file("press.yaml", "start: [0, 0, 0.02]\nactions:\n  - hold: {duration: 0.1}\n");
  const Config p = Config::parse(
      "script: press.yaml\ncentre: [0, 0, 0.1]\nhand_stiffness: 300\nbackdrive_friction: 0\npassivity: "
      "off\nmax_damping: 5\n"
      "source_timeout: 0.02\nanswer_wait: 0.0005\nreport: out/r.json\n",
      dir.file("d.yaml"), "params");
  const DeviceConfig c = device_config(p, 1000);
  EXPECT_FALSE(c.replay);
  EXPECT_EQ(c.source, dir.file("press.yaml"));
  EXPECT_EQ(c.spec.centre, Eigen::Vector3d(0, 0, 0.1));
  EXPECT_EQ(c.spec.servo_hz, 1000);
  EXPECT_EQ(c.hand.stiffness, 300);
  EXPECT_EQ(c.spec.backdrive_friction, 0);
  EXPECT_FALSE(c.passivity);
  EXPECT_EQ(c.max_damping, 5);
  EXPECT_EQ(c.source_timeout, 0.02);
  EXPECT_EQ(c.answer_wait, 0.0005);
  EXPECT_EQ(c.report, dir.file("out/r.json"));
  EXPECT_NE(dynamic_cast<SimulatedOmni*>(make_device(c).get()), nullptr);
}

TEST(DeviceConfig, AnswerWaitDefaultsToItsShareOfTheTickAndAReplayPlaysItsFile) {
  tests::TempDir dir;
  dir.file("t.csv", "time_s,x,y,z,buttons\n0,0,0,0.02,0\n0.001,0,0,0.0199,0\n");
  const DeviceConfig c = device_config(Config::parse("device: replay\nreplay: t.csv\n", dir.file("d.yaml"), "p"), 500);
  EXPECT_TRUE(c.replay);
  EXPECT_DOUBLE_EQ(c.answer_wait, kAnswerShare * 0.002);
  EXPECT_TRUE(c.passivity);
  EXPECT_NE(dynamic_cast<Replay*>(make_device(c).get()), nullptr);
}

TEST(DeviceConfig, MistakesAreNamedAtTheirPlace) {
  tests::TempDir dir;
  const auto error = [&](const std::string& text) {
    return message_of<ConfigError>([&] { device_config(Config::parse(text, dir.file("d.yaml"), "p"), 1000); });
  };
  EXPECT_EQ(error("device: simulated\n"),
            "hcosim_haptic: params.script (a virtual-user script) is required; docs/haptic.md");
  EXPECT_EQ(error("script: none.yaml\n"), dir.file("d.yaml") + ":1:9: 'script': no file " + dir.file("none.yaml"));
  dir.file("s.yaml", "actions: []\n");
  EXPECT_EQ(error("script: s.yaml\nanswer_wait: 0.001\n"),
            dir.file("d.yaml") + ":2:14: 'answer_wait' = 0.001 is outside [0, 0.0009]");
  EXPECT_EQ(error("script: s.yaml\ndevice: phantom\n"),
            dir.file("d.yaml") + ":2:9: 'device' must be one of simulated, replay, not 'phantom'");
}

}  // namespace
}  // namespace hcosim::adapters::device
