#include "adapters/device/wall_rig.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>

#include "adapters/device/simulated_omni.h"
#include "models/haptic/passivity.h"

namespace hcosim::adapters::device {

namespace {

models::haptic::Script press_script(const WallRig& r) {
  using K = models::haptic::Action::Kind;
  const Eigen::Vector3d above = r.wall.point + 0.002 * r.wall.normal;
  models::haptic::Script s;
  s.start = r.wall.point + 0.01 * r.wall.normal;
  models::haptic::Action a;
  a.speed = r.speed;
  a.kind = K::move_to, a.to = above, s.actions.push_back(a);
  a = {}, a.speed = r.speed, a.kind = K::press, a.direction = -r.wall.normal, a.depth = 0.002 + r.press_depth;
  s.actions.push_back(a);
  a = {}, a.kind = K::hold, a.duration = r.hold_s, s.actions.push_back(a);
  a = {}, a.speed = r.speed, a.kind = K::release, s.actions.push_back(a);
  a = {}, a.kind = K::hold, a.duration = 0.2, s.actions.push_back(a);
  return s;
}

}  // namespace

double balance_depth(const WallRig& r) {
  return r.hand.stiffness * r.press_depth / (r.hand.stiffness + r.wall.stiffness);
}

WallRun run_wall(const WallRig& r) {
  if (!(r.delay_s >= 0) || !std::isfinite(r.delay_s))
    throw std::invalid_argument("wall rig: delay must be finite and >= 0");
  SimulatedOmni omni(r.spec, r.hand, press_script(r));
  const double dt = 1 / r.spec.servo_hz;
  models::haptic::PassivityController pc(dt, r.max_damping, r.reservoir);
  const int delay_ticks = int(std::lround(r.delay_s / dt));
  std::deque<Eigen::Vector3d> line(delay_ticks, Eigen::Vector3d::Zero());
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();
  WallRun out;
  std::vector<double> held;         // tip depth during the hold
  constexpr std::size_t kHold = 2;  // the script's hold action
  while (!omni.finished()) {
    const bool holding = omni.user().action() == kHold;
    const Frame f = omni.begin_frame();
    double depth;
    line.push_back(models::haptic::wall_force(r.wall, f.position, f.velocity, &depth));
    const Eigen::Vector3d env = line.front();
    line.pop_front();
    const Eigen::Vector3d cmd = r.passivity ? pc.filter(env, f.velocity, applied) : env;
    const Eigen::Vector3d v0 = omni.tip().v;
    applied = omni.end_frame(cmd);
    out.energy_out_j += applied.dot(0.5 * (v0 + omni.tip().v)) * dt;
    out.max_energy_out_j = std::max(out.max_energy_out_j, out.energy_out_j);
    out.max_force_n = std::max(out.max_force_n, applied.norm());
    if (holding) held.push_back((r.wall.point - omni.tip().x).dot(r.wall.normal));
  }
  const std::vector<double> settled(held.begin() + held.size() / 2, held.end());
  if (!settled.empty()) {
    const auto [lo, hi] = std::minmax_element(settled.begin(), settled.end());
    out.peak_to_peak_m = *hi - *lo;
    double sum = 0;
    for (double d : settled) sum += d;
    out.depth_m = sum / settled.size();
  }
  out.saturated = omni.saturated();
  out.stable = out.peak_to_peak_m < 4 * r.spec.resolution && out.max_energy_out_j < 1e-3;
  return out;
}

}  // namespace hcosim::adapters::device
