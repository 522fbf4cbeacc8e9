#include "adapters/device/device_config.h"

#include "adapters/device/replay.h"
#include "adapters/device/script_yaml.h"
#include "adapters/device/simulated_omni.h"

namespace hcosim::adapters::device {

DeviceConfig device_config(const Config& p, double servo_hz) {
  p.allow_only({"device", "replay", "script", "passivity", "source_timeout", "max_damping", "reservoir",
                "hand_stiffness", "hand_damping", "backdrive_friction", "centre", "answer_wait", "report",
                "tip_radius"});
  DeviceConfig c;
  c.replay = p.text("device", "simulated", {"simulated", "replay"}) == "replay";
  c.source = p.path(c.replay ? "replay" : "script");
  if (c.source.empty())
    throw ConfigError(std::string("hcosim_haptic: params.") +
                      (c.replay ? "replay (a recorded trajectory, CSV)" : "script (a virtual-user script)") +
                      " is required; docs/haptic.md");
  const auto centre = p.vec3("centre", {0, 0, 0});
  c.spec.centre = {centre[0], centre[1], centre[2]};
  c.spec.servo_hz = servo_hz;
  c.hand.stiffness = p.number("hand_stiffness", c.hand.stiffness, 1, 1e4);
  c.hand.damping = p.number("hand_damping", c.hand.damping, 0, 1e3);
  c.spec.backdrive_friction = p.number("backdrive_friction", c.spec.backdrive_friction, 0, 1);
  c.passivity = p.on("passivity", c.passivity);
  c.max_damping = p.number("max_damping", c.max_damping, 1e-3, 1e3);
  c.reservoir = p.number("reservoir", c.reservoir, 1e-9, 10);
  c.source_timeout = p.number("source_timeout", c.source_timeout, 1e-3, 10);
  const double dt = 1 / servo_hz;
  c.answer_wait = p.number("answer_wait", kAnswerShare * dt, 0, 0.9 * dt);
  c.report = p.output_path("report");
  c.tip_radius = p.number("tip_radius", c.tip_radius, 0, kMaxTipRadius);
  return c;
}

std::unique_ptr<Device> make_device(const DeviceConfig& c) {
  if (c.replay) return std::make_unique<Replay>(c.spec, load_trajectory(c.source));
  return std::make_unique<SimulatedOmni>(c.spec, c.hand, load_script(c.source));
}

}  // namespace hcosim::adapters::device
