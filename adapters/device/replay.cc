#include "adapters/device/replay.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hcosim::adapters::device {

std::vector<Sample> load_trajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  auto fail = [&](int line, const std::string& what) {
    throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
  };
  std::string line;
  if (!std::getline(in, line) || line.rfind("time_s,x,y,z,buttons", 0) != 0)
    fail(1, "the header must be 'time_s,x,y,z,buttons'");
  std::vector<Sample> out;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream row(line);
    double v[4];
    char comma;
    long long buttons;
    if (!(row >> v[0] >> comma >> v[1] >> comma >> v[2] >> comma >> v[3] >> comma >> buttons))
      fail(n, "expected 5 comma-separated numbers");
    for (double x : v)
      if (!std::isfinite(x)) fail(n, "non-finite value");
    if (buttons < 0 || buttons > 0xffffffffLL) fail(n, "buttons out of range");
    if (!out.empty() && v[0] <= out.back().t) fail(n, "time does not increase");
    out.push_back({v[0], {v[1], v[2], v[3]}, std::uint32_t(buttons)});
  }
  if (out.empty()) fail(1, "no samples");
  return out;
}

Replay::Replay(const models::haptic::OmniSpec& spec, std::vector<Sample> trajectory)
    : Device(spec), samples_(std::move(trajectory)) {
  if (samples_.empty()) throw std::invalid_argument("replay: empty trajectory");
}

Eigen::Vector3d Replay::at(double t, std::uint32_t* buttons) const {
  const auto next =
      std::upper_bound(samples_.begin(), samples_.end(), t, [](double v, const Sample& s) { return v < s.t; });
  if (next == samples_.begin()) return *buttons = next->buttons, next->x;
  const auto prev = next - 1;
  *buttons = prev->buttons;
  if (next == samples_.end()) return prev->x;
  const double a = (t - prev->t) / (next->t - prev->t);
  return prev->x + a * (next->x - prev->x);
}

Frame Replay::read_frame() {
  const double dt = 1 / spec().servo_hz;
  const double t = now();
  Frame f;
  f.time_s = t;
  std::uint32_t before;
  f.position = at(t, &f.buttons);
  f.velocity = (f.position - at(t - dt, &before)) / dt;
  return f;
}

}  // namespace hcosim::adapters::device
