// The virtual user: a scripted hand that moves the stylus. It sets the
// target the hand pulls the stylus toward (haptic/omni.h: Hand); contact
// forces push back, so the stylus stops short of the target inside a stiff
// object as it would in a person's hand. Deterministic: the target depends
// only on the script, the tick and the forces rendered.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace hcosim::models::haptic {

struct Action {
  enum class Kind { move_to, press, hold, stroke, tap, release };
  Kind kind = Kind::hold;
  Eigen::Vector3d to = Eigen::Vector3d::Zero();           // move_to: world m; stroke: offset, m
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();  // press, tap: unit, into the object
  double depth = 0;      // press, tap: m the target travels along direction (press: 0 = go by force)
  double force = 0;      // press: N; stops when the rendered force against direction reaches it,
                         // or after kMaxPressTravel if nothing pushes back
  double speed = 0.02;   // move_to, press, stroke, release: m/s
  double duration = 0;   // hold, tap: s
  unsigned buttons = 0;  // bit i: button i held while the action runs (button 0 grabs a deformable object)
  int line = 0;          // script line, for messages
};

inline constexpr double kMaxPressTravel = 0.2;  // m

struct Script {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  // hand target at t = 0, world m
  std::vector<Action> actions;
};

const char* name(Action::Kind kind);

// What makes no sense in `action` (non-positive speed, a press with
// neither or both of depth and force, a zero direction, a negative
// duration...), or "" when nothing does.
std::string problem(const Action& action);

// Throws std::invalid_argument naming the first bad action and its line.
void check(const Script& script);

class VirtualUser {
 public:
  VirtualUser(Script script, double dt);

  // The hand target for the next tick, given the force the device rendered
  // on the stylus this tick (world frame, N).
  Eigen::Vector3d next(const Eigen::Vector3d& rendered_force);

  bool done() const { return index_ >= script_.actions.size(); }
  // The buttons held by the action that set the latest target.
  unsigned buttons() const { return buttons_; }
  std::size_t action() const { return index_; }  // index of the running action
  const Script& script() const { return script_; }

 private:
  void advance();

  Script script_;
  double dt_;
  std::size_t index_ = 0;
  unsigned buttons_ = 0;
  double elapsed_ = 0;  // s in the running action
  Eigen::Vector3d target_;
  Eigen::Vector3d from_;          // target when the running action began
  Eigen::Vector3d press_origin_;  // target when the last press or tap began
};

}  // namespace hcosim::models::haptic
