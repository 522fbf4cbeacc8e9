#include "adapters/device/script_yaml.h"

#include <cmath>

#include "adapters/config.h"

namespace hcosim::adapters::device {
namespace {

Eigen::Vector3d vec3(const std::string& file, const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3) throw config_error(file, n, "'" + key + "' must be [x, y, z]");
  return {config_number(file, n[0], key), config_number(file, n[1], key), config_number(file, n[2], key)};
}

models::haptic::Action action(const std::string& file, const YAML::Node& item) {
  using K = models::haptic::Action::Kind;
  const std::vector<std::string> kinds{"move_to", "press", "hold", "stroke", "tap", "release"};
  if (!item.IsMap() || item.size() != 1)
    throw config_error(file, item, "each action is a one-key map, one of " + join(kinds));
  const std::string kind = item.begin()->first.Scalar();
  const YAML::Node body = item.begin()->second;
  models::haptic::Action a;
  a.line = item.Mark().line + 1;
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
    check_keys(file, item, kinds);  // throws, with the nearest action name
  if (!body.IsMap()) throw config_error(file, body, "'" + kind + "' takes a map of " + join(keys));
  keys.push_back("buttons");
  check_keys(file, body, keys);
  if (kind == "move_to" && !body["to"]) throw config_error(file, body, "move_to needs 'to'");
  if (kind == "stroke" && !body["by"]) throw config_error(file, body, "stroke needs 'by'");
  if (kind == "hold" && !body["duration"]) throw config_error(file, body, "hold needs 'duration'");
  if (body["to"]) a.to = vec3(file, body["to"], "to");
  if (body["by"]) a.to = vec3(file, body["by"], "by");
  if (body["direction"]) a.direction = vec3(file, body["direction"], "direction");
  if (body["depth"]) a.depth = config_number(file, body["depth"], "depth");
  if (body["force"]) a.force = config_number(file, body["force"], "force");
  if (body["speed"]) a.speed = config_number(file, body["speed"], "speed");
  if (body["duration"]) a.duration = config_number(file, body["duration"], "duration");
  if (body["buttons"]) {
    const double b = config_number(file, body["buttons"], "buttons");
    if (!(b >= 0 && b <= 15 && b == std::floor(b)))
      throw config_error(file, body["buttons"], "'buttons' is a bit mask of the Omni's buttons, a whole number 0..15");
    a.buttons = unsigned(b);
  }
  if (const std::string p = models::haptic::problem(a); !p.empty()) throw config_error(file, item, kind + ": " + p);
  return a;
}

}  // namespace

models::haptic::Script load_script(const std::string& path) {
  const YAML::Node root = load_yaml(path);
  if (!root.IsMap()) throw ConfigError(path + ":1:1: a script must be a YAML map with start and actions");
  check_keys(path, root, {"start", "actions"});
  models::haptic::Script s;
  if (root["start"]) s.start = vec3(path, root["start"], "start");
  const YAML::Node actions = root["actions"];
  if (!actions || !actions.IsSequence()) throw ConfigError(path + ":1:1: a script needs a list of 'actions'");
  for (const YAML::Node& item : actions) s.actions.push_back(action(path, item));
  return s;
}

}  // namespace hcosim::adapters::device
