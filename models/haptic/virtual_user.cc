#include "models/haptic/virtual_user.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hcosim::models::haptic {

const char* name(Action::Kind k) {
  switch (k) {
    case Action::Kind::move_to:
      return "move_to";
    case Action::Kind::press:
      return "press";
    case Action::Kind::hold:
      return "hold";
    case Action::Kind::stroke:
      return "stroke";
    case Action::Kind::tap:
      return "tap";
    case Action::Kind::release:
      return "release";
  }
  return "?";
}

std::string problem(const Action& a) {
  if (!a.to.allFinite()) return "'to' must be finite";
  if (!(a.speed > 0) || !std::isfinite(a.speed)) return "speed must be finite and > 0";
  if (!(a.duration >= 0) || !std::isfinite(a.duration)) return "duration must be finite and >= 0";
  if (!(a.depth >= 0) || !std::isfinite(a.depth)) return "depth must be finite and >= 0";
  if (!(a.force >= 0) || !std::isfinite(a.force)) return "force must be finite and >= 0";
  if (!a.direction.allFinite() || a.direction.norm() < 1e-9) return "direction must be a finite nonzero vector";
  if (a.kind == Action::Kind::press && (a.depth > 0) == (a.force > 0)) return "give exactly one of depth and force";
  if (a.kind == Action::Kind::tap && (a.depth <= 0 || a.duration <= 0)) return "a tap needs depth > 0 and duration > 0";
  return "";
}

void check(const Script& s) {
  if (!s.start.allFinite()) throw std::invalid_argument("script: start must be finite");
  for (std::size_t i = 0; i < s.actions.size(); ++i) {
    const Action& a = s.actions[i];
    if (const std::string p = problem(a); !p.empty())
      throw std::invalid_argument("script: action " + std::to_string(i + 1) + " (" + name(a.kind) +
                                  (a.line ? ", line " + std::to_string(a.line) : "") + "): " + p);
  }
}

VirtualUser::VirtualUser(Script script, double dt)
    : script_(std::move(script)), dt_(dt), target_(script_.start), from_(script_.start), press_origin_(script_.start) {
  check(script_);
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("virtual user: dt must be finite and > 0");
  for (Action& a : script_.actions) a.direction.normalize();
}

void VirtualUser::advance() {
  ++index_;
  elapsed_ = 0;
  from_ = target_;
}

Eigen::Vector3d VirtualUser::next(const Eigen::Vector3d& rendered) {
  if (done()) return buttons_ = 0, target_;
  const Action& a = script_.actions[index_];
  buttons_ = a.buttons;
  if (elapsed_ == 0 && (a.kind == Action::Kind::press || a.kind == Action::Kind::tap)) press_origin_ = target_;
  elapsed_ += dt_;
  // Straight toward `goal` at the action's speed; true on arrival.
  auto travel = [&](const Eigen::Vector3d& goal) {
    const Eigen::Vector3d d = goal - from_;
    const double len = d.norm(), s = a.speed * elapsed_;
    if (s >= len) {
      target_ = goal;
      return true;
    }
    target_ = from_ + d * (s / len);
    return false;
  };
  bool finished = false;
  switch (a.kind) {
    case Action::Kind::move_to:
      finished = travel(a.to);
      break;
    case Action::Kind::stroke:
      finished = travel(from_ + a.to);
      break;
    case Action::Kind::release:
      finished = travel(press_origin_);
      break;
    case Action::Kind::hold:
      finished = elapsed_ >= a.duration - 1e-12;
      break;
    case Action::Kind::press:
      if (a.force > 0) {
        // Deeper until the object pushes back with the asked force.
        if (-rendered.dot(a.direction) >= a.force || a.speed * elapsed_ > kMaxPressTravel)
          finished = true;
        else
          target_ = from_ + a.direction * (a.speed * elapsed_);
      } else {
        finished = travel(from_ + a.direction * a.depth);
      }
      break;
    case Action::Kind::tap: {
      const double phase = std::min(elapsed_ / a.duration, 1.0);
      target_ = press_origin_ + a.direction * (a.depth * (1 - std::abs(2 * phase - 1)));
      finished = phase >= 1;
      break;
    }
  }
  const Eigen::Vector3d out = target_;
  if (finished) advance();
  return out;
}

}  // namespace hcosim::models::haptic
