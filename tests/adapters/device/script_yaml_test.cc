// Virtual-user scripts read from YAML: every action, errors that name the
// file and line, buttons held only by their action.
#include <gtest/gtest.h>

#include "adapters/config.h"
#include "adapters/device/script_yaml.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters::device {

using namespace models::haptic;

namespace {

using K = Action::Kind;

class ScriptFiles : public ::testing::Test {
 protected:
  tests::TempDir dir;
  std::string write(const std::string& name, const std::string& text) { return dir.file(name, text); }
  // The ConfigError message of loading `text`.
  std::string error(const std::string& text) {
    const std::string path = write("bad.yaml", text);
    try {
      adapters::device::load_script(path);
    } catch (const adapters::ConfigError& e) {
      return e.what();
    }
    return "(no error)";
  }
};

TEST_F(ScriptFiles, ReadsEveryAction) {
  const Script s = adapters::device::load_script(write("ok.yaml", R"(start: [0, 0, 0.02]
actions:
  - move_to: {to: [0, 0, 0.005], speed: 0.05}
  - press: {force: 1.5, direction: [0, 0, -2], speed: 0.01}
  - hold: {duration: 0.5}
  - stroke: {by: [0.02, 0, 0], speed: 0.02}
  - tap: {depth: 0.002, duration: 0.1}
  - release: {speed: 0.02}
)"));
  ASSERT_EQ(s.actions.size(), 6u);
  EXPECT_EQ(s.start, Eigen::Vector3d(0, 0, 0.02));
  EXPECT_EQ(s.actions[1].kind, K::press);
  EXPECT_EQ(s.actions[1].force, 1.5);
  EXPECT_EQ(s.actions[1].line, 4);
  EXPECT_EQ(s.actions[3].to, Eigen::Vector3d(0.02, 0, 0));
  EXPECT_EQ(s.actions[4].duration, 0.1);
}

TEST_F(ScriptFiles, ErrorsNameTheFileAndLine) {
  EXPECT_NE(error("actions:\n  - hold: {duration: 1}\n  - prss: {depth: 0.01}\n")
                .find("bad.yaml:3:5: unknown key 'prss'; did you mean 'press'?"),
            std::string::npos);
  EXPECT_NE(error("actions:\n  - press: {depth: 0.01, force: 1}\n")
                .find("bad.yaml:2:5: press: give exactly one of depth and force"),
            std::string::npos);
  EXPECT_NE(error("actions:\n  - move_to: {to: [0, 0], speed: 1}\n").find("bad.yaml:2:19: 'to' must be [x, y, z]"),
            std::string::npos);
  EXPECT_NE(
      error("actions:\n  - hold: {duration: fast}\n").find("bad.yaml:2:22: 'duration' must be a number, not 'fast'"),
      std::string::npos);
  EXPECT_NE(error("start: [0, 0\n").find("bad.yaml:"), std::string::npos);
  const std::string buttons = error("actions:\n  - hold: {duration: 1, buttons: 1.5}\n");
  EXPECT_NE(buttons.find("bad.yaml:2:34: 'buttons' is a bit mask"), std::string::npos) << buttons;
}

TEST_F(ScriptFiles, ButtonsAreHeldOnlyByTheirAction) {
  const Script s = adapters::device::load_script(write("grab.yaml", R"(start: [0, 0, 0.02]
actions:
  - hold: {duration: 0.002}
  - stroke: {by: [0, 0, 0.001], speed: 0.5, buttons: 1}
  - hold: {duration: 0.002, buttons: 3}
  - hold: {duration: 0.002}
)"));
  EXPECT_EQ(s.actions[1].buttons, 1u);
  VirtualUser u(s, 0.001);
  std::vector<unsigned> held;
  while (!u.done()) u.next(Eigen::Vector3d::Zero()), held.push_back(u.buttons());
  u.next(Eigen::Vector3d::Zero());
  EXPECT_EQ(held, (std::vector<unsigned>{0, 0, 1, 1, 1, 3, 3, 0, 0}));  // the stroke: 2 ticks and its arrival
  EXPECT_EQ(u.buttons(), 0u);                                           // done: nothing held
}

}  // namespace
}  // namespace hcosim::adapters::device
