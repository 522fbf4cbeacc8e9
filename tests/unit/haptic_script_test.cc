// Virtual-user scripts: each action's semantics, and YAML files whose
// errors name the file and line.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "adapters/config.h"
#include "adapters/device/script_yaml.h"

namespace hcosim::models::haptic {
namespace {

using K = Action::Kind;
constexpr double kDt = 1e-3;

Action act(K kind) {
  Action a;
  a.kind = kind;
  return a;
}

// Runs the user with the force a wall at z = 0 (k = 1000 N/m) would put on
// the target; returns the targets, one per tick.
std::vector<Eigen::Vector3d> play(const Script& s, int max_ticks = 100000) {
  VirtualUser u(s, kDt);
  std::vector<Eigen::Vector3d> out;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  while (!u.done() && int(out.size()) < max_ticks) {
    out.push_back(u.next(force));
    force = Eigen::Vector3d(0, 0, 1000 * std::max(0.0, -out.back().z()));
  }
  return out;
}

TEST(HapticScript, MoveToTravelsAtItsSpeedAndHoldWaits) {
  Script s;
  Action m = act(K::move_to);
  m.to = {0.01, 0, 0}, m.speed = 0.02;
  Action h = act(K::hold);
  h.duration = 0.1;
  s.actions = {m, h};
  const auto t = play(s);
  EXPECT_EQ(t.size(), 500u + 100u);  // 1 cm at 2 cm/s, then 0.1 s
  EXPECT_NEAR(t[249].x(), 0.005, 1e-12);
  EXPECT_EQ(t.back(), Eigen::Vector3d(0.01, 0, 0));
}

TEST(HapticScript, PressByDepthOrForceThenReleaseToWhereItBegan) {
  Script s;
  s.start = {0, 0, 0.001};
  Action by_depth = act(K::press);
  by_depth.depth = 0.003, by_depth.speed = 0.01;
  Action back = act(K::release);
  Action by_force = act(K::press);
  by_force.force = 1.5, by_force.speed = 0.01;
  s.actions = {by_depth, back, by_force};
  const auto t = play(s);
  // 3 mm down at 1 cm/s, back, then down until the wall pushes 1.5 N.
  EXPECT_NEAR(t[299].z(), -0.002, 1e-12);
  EXPECT_NEAR(t[299 + 150].z(), 0.001, 1e-12);
  EXPECT_NEAR(t.back().z(), -0.0015, 1e-5);
}

TEST(HapticScript, StrokeMovesByItsOffsetAndTapComesBack) {
  Script s;
  Action st = act(K::stroke);
  st.to = {0.01, 0.01, 0}, st.speed = 0.01;
  Action tap = act(K::tap);
  tap.depth = 0.002, tap.duration = 0.1;
  s.actions = {st, tap};
  const auto t = play(s);
  const Eigen::Vector3d end_of_stroke(0.01, 0.01, 0);
  EXPECT_LT((t[t.size() - 101] - end_of_stroke).norm(), 1e-12);
  EXPECT_NEAR(t[t.size() - 51].z(), -0.002, 1e-12);
  EXPECT_LT((t.back() - end_of_stroke).norm(), 1e-12);
}

TEST(HapticScript, SameScriptSameTargets) {
  Script s;
  Action p = act(K::press);
  p.force = 2, p.speed = 0.02;
  s.actions = {p, act(K::release)};
  EXPECT_EQ(play(s), play(s));
}

TEST(HapticScript, NonsenseIsRefusedWithTheActionNamed) {
  Script s;
  Action p = act(K::press);  // neither depth nor force
  p.line = 7;
  s.actions = {act(K::hold), p};
  try {
    VirtualUser u(s, kDt);
    FAIL() << "accepted a press with neither depth nor force";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("action 2 (press, line 7): give exactly one of depth and force"),
              std::string::npos)
        << e.what();
  }
}

class ScriptFiles : public ::testing::Test {
 protected:
  std::filesystem::path dir = std::filesystem::temp_directory_path() / ("hcosim_script_" + std::to_string(::getpid()));
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) {
    const auto p = dir / name;
    std::ofstream(p) << text;
    return p.string();
  }
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
}  // namespace hcosim::models::haptic
