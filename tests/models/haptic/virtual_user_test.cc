// The virtual user's actions: move, hold, press by depth or force and
// release, stroke and tap; the same script gives the same targets; nonsense
// is refused with the action named.
#include <gtest/gtest.h>

#include "models/haptic/virtual_user.h"

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

}  // namespace
}  // namespace hcosim::models::haptic
