#include "adapters/device/script_yaml.h"

#include <cmath>
#include <limits>

#include "adapters/config.h"

namespace hcosim::adapters::device {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Vector3d vec3(const Config& c, const std::string& key, const Eigen::Vector3d& fallback) {
  const auto v = c.vec3(key, {fallback.x(), fallback.y(), fallback.z()});
  return {v[0], v[1], v[2]};
}

models::haptic::Action action(const Config& item) {
  using K = models::haptic::Action::Kind;
  const std::vector<std::string> kinds{"move_to", "press", "hold", "stroke", "tap", "release"};
  const YAML::Node& n = item.node();
  if (n.size() != 1) item.fail("", "each action is a one-key map, one of " + join(kinds));
  const std::string kind = n.begin()->first.Scalar();
  models::haptic::Action a;
  a.line = n.Mark().line + 1;
  std::vector<std::string> keys;
  if (kind == "move_to")
    a.kind = K::move_to, keys = {"to", "speed"};
  else if (kind == "press")
    a.kind = K::press, keys = {"depth", "force", "direction", "speed"};
  else if (kind == "hold")
    a.kind = K::hold, keys = {"duration"};
  else if (kind == "stroke")
    a.kind = K::stroke, keys = {"by", "speed"};
  else if (kind == "tap")
    a.kind = K::tap, keys = {"depth", "duration", "direction"};
  else if (kind == "release")
    a.kind = K::release, keys = {"speed"};
  else
    item.allow_only(kinds);  // throws, with the nearest action name
  if (!n.begin()->second.IsMap()) item.fail(kind, "'" + kind + "' takes a map of " + join(keys));
  const Config body = item.map(kind);
  keys.push_back("buttons");
  body.allow_only(keys);
  if (kind == "move_to") body.require({"to"}, kind);
  if (kind == "stroke") body.require({"by"}, kind);
  if (kind == "hold") body.require({"duration"}, kind);
  a.to = vec3(body, kind == "stroke" ? "by" : "to", a.to);
  a.direction = vec3(body, "direction", a.direction);
  // Signs and sizes are the model's to judge (models::haptic::problem).
  a.depth = body.number("depth", a.depth, -kInf, kInf);
  a.force = body.number("force", a.force, -kInf, kInf);
  a.speed = body.number("speed", a.speed, -kInf, kInf);
  a.duration = body.number("duration", a.duration, -kInf, kInf);
  const double buttons = body.number("buttons", a.buttons, -kInf, kInf);
  if (!(buttons >= 0 && buttons <= 15 && buttons == std::floor(buttons)))
    body.fail("buttons", "'buttons' is a bit mask of the Omni's buttons, a whole number 0..15");
  a.buttons = unsigned(buttons);
  if (const std::string p = models::haptic::problem(a); !p.empty()) item.fail("", kind + ": " + p);
  return a;
}

}  // namespace

models::haptic::Script load_script(const std::string& path) {
  const Config root = Config::load(path, "a script (start and actions)");
  root.allow_only({"start", "actions"});
  models::haptic::Script s;
  s.start = vec3(root, "start", s.start);
  if (!root.has("actions") || !root.node()["actions"].IsSequence())
    throw ConfigError(path + ":1:1: a script needs a list of 'actions'");
  for (const Config& item : root.list("actions")) s.actions.push_back(action(item));
  return s;
}

}  // namespace hcosim::adapters::device
