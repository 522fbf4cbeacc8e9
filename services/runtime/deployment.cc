#include "deployment.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "participant.h"

namespace hcosim::rt {
namespace {

ServiceSpec parse_service(const std::string& file, const YAML::Node& node) {
  if (!node.IsMap()) throw config_error(file, node, "each service must be a map with name, kind and rate");
  check_keys(file, node, {"name", "kind", "rate", "params", "on_failure"});
  ServiceSpec s;
  s.line = node.Mark().line + 1;
  s.where = file + ":" + std::to_string(s.line) + ":" + std::to_string(node.Mark().column + 1);
  for (const char* key : {"name", "kind", "rate"})
    if (!node[key]) throw config_error(file, node, std::string("service is missing required key '") + key + "'");
  s.name = config_text(file, node["name"], "name");
  if (!std::regex_match(s.name, std::regex("[a-z][a-z0-9_]{0,30}")))
    throw config_error(file, node["name"],
                       "service name '" + s.name + "' must be 1 to 31 of a-z, 0-9, _ and start with a letter");
  s.kind = config_text(file, node["kind"], "kind");
  if (!std::regex_match(s.kind, std::regex("[a-z][a-z0-9_]*")))
    throw config_error(file, node["kind"], "service kind '" + s.kind + "' must be a-z, 0-9 and _");
  s.rate_hz = config_number(file, node["rate"], "rate");
  if (s.rate_hz <= 0 || s.rate_hz > 1e5)
    throw config_error(file, node["rate"], "'rate' must be in (0, 100000] Hz");
  if (const YAML::Node n = node["on_failure"]) {
    s.where = file + ":" + std::to_string(n.Mark().line + 1) + ":" + std::to_string(n.Mark().column + 1);
    const std::string v = config_text(file, n, "on_failure");
    if (v == "stop_all") s.on_failure = OnFailure::kStopAll;
    else if (v == "restart") s.on_failure = OnFailure::kRestart;
    else if (v == "ignore") s.on_failure = OnFailure::kIgnore;
    else throw config_error(file, n, "'on_failure' must be stop_all, restart or ignore, not '" + v + "'");
  }
  s.params = node["params"] ? node["params"] : YAML::Node(YAML::NodeType::Map);
  if (!s.params.IsMap()) throw config_error(file, node["params"], "'params' must be a map");
  return s;
}

}  // namespace

const char* to_string(Mode m) { return m == Mode::kLockstep ? "lockstep" : "realtime"; }

const char* to_string(OnFailure f) {
  return f == OnFailure::kRestart ? "restart" : f == OnFailure::kIgnore ? "ignore" : "stop_all";
}

void check_policy(const ServiceSpec& s, Mode mode) {
  if (mode == Mode::kLockstep && s.on_failure != OnFailure::kStopAll)
    throw ConfigError(s.where + ": on_failure: " + to_string(s.on_failure) + " needs mode realtime (in lockstep the "
                      "clock waits on every follower at every step: one cannot be missing or rejoin)");
}

Mode parse_mode(const std::string& s) {
  if (s == "realtime") return Mode::kRealtime;
  if (s == "lockstep") return Mode::kLockstep;
  throw std::invalid_argument("mode must be 'realtime' or 'lockstep', not '" + s + "'");
}

Deployment load_deployment(const std::string& path) {
  const YAML::Node root = load_yaml(path);
  if (!root.IsMap()) throw ConfigError(path + ":1:1: a deployment must be a YAML map");
  check_keys(path, root, {"domain", "mode", "step", "duration", "services"});

  Deployment d;
  d.file = path;
  if (auto n = root["domain"]) {
    const double v = config_number(path, n, "domain");
    if (v != std::floor(v) || v < 0 || v > kMaxDomain)
      throw config_error(path, n, "'domain' must be a whole number in 0.." + std::to_string(kMaxDomain));
    d.domain = static_cast<int>(v);
  }
  if (auto n = root["mode"]) {
    try {
      d.mode = parse_mode(config_text(path, n, "mode"));
    } catch (const std::invalid_argument& e) {
      throw config_error(path, n, e.what());
    }
  }
  if (auto n = root["step"]) {
    d.step_s = config_number(path, n, "step");
    if (d.step_s < 1e-6 || d.step_s > 1) throw config_error(path, n, "'step' must be in [1e-6, 1] s");
  }
  if (auto n = root["duration"]) {
    d.duration_s = config_number(path, n, "duration");
    if (d.duration_s < 0) throw config_error(path, n, "'duration' must not be negative");
  }
  if (auto n = root["services"]) {
    if (!n.IsSequence()) throw config_error(path, n, "'services' must be a list");
    std::set<std::string> names;
    for (const auto& s : n) {
      ServiceSpec spec = parse_service(path, s);
      if (spec.name == "clock")
        throw config_error(path, s["name"], "the name 'clock' is reserved for the lockstep master");
      if (!names.insert(spec.name).second)
        throw config_error(path, s["name"], "service name '" + spec.name + "' is used twice");
      check_policy(spec, d.mode);
      d.services.push_back(std::move(spec));
    }
  }
  return d;
}

Params::Params(std::string file, YAML::Node node) : file_(std::move(file)), node_(std::move(node)) {}

double Params::number(const std::string& key, double fallback, double lo, double hi) const {
  if (!node_ || !node_[key]) return fallback;
  const YAML::Node n = node_[key];
  const double v = config_number(file_, n, key);
  if (v < lo || v > hi)
    throw config_error(file_, n, "'" + key + "' = " + n.Scalar() + " is outside [" + std::to_string(lo) + ", " +
                                     std::to_string(hi) + "]");
  return v;
}

std::string Params::text(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const {
  if (!node_ || !node_[key]) return fallback;
  const std::string v = config_text(file_, node_[key], key);
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
    throw config_error(file_, node_[key], "'" + key + "' must be one of " + join(allowed) + ", not '" + v + "'");
  return v;
}

std::string Params::string(const std::string& key, const std::string& fallback) const {
  if (!node_ || !node_[key]) return fallback;
  return config_text(file_, node_[key], key);
}

std::string Params::path(const std::string& key) const {
  if (!node_ || !node_[key]) return "";
  std::filesystem::path p = config_text(file_, node_[key], key);
  if (p.is_relative()) p = std::filesystem::path(file_).parent_path() / p;
  if (!std::filesystem::exists(p)) throw config_error(file_, node_[key], "'" + key + "': no file " + p.string());
  return p.string();
}

std::string Params::output_path(const std::string& key) const {
  if (!node_ || !node_[key]) return "";
  std::filesystem::path p = config_text(file_, node_[key], key);
  if (p.is_relative()) p = std::filesystem::path(file_).parent_path() / p;
  return p.string();
}

std::array<double, 3> Params::vec3(const std::string& key, const std::array<double, 3>& fallback) const {
  if (!node_ || !node_[key]) return fallback;
  const YAML::Node n = node_[key];
  if (!n.IsSequence() || n.size() != 3) throw config_error(file_, n, "'" + key + "' must be [x, y, z]");
  return {config_number(file_, n[0], key), config_number(file_, n[1], key), config_number(file_, n[2], key)};
}

std::vector<Params> Params::list(const std::string& key) const {
  std::vector<Params> out;
  if (!node_ || !node_[key]) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) throw config_error(file_, n, "'" + key + "' must be a list");
  for (const YAML::Node& item : n) {
    if (!item.IsMap()) throw config_error(file_, item, "each entry of '" + key + "' must be a map of keys");
    out.emplace_back(file_, item);
  }
  return out;
}

void Params::fail(const std::string& key, const std::string& what) const {
  throw config_error(file_, node_ && node_[key] ? node_[key] : node_, what);
}

void Params::allow_only(const std::vector<std::string>& allowed) const {
  if (node_ && node_.IsMap()) check_keys(file_, node_, allowed);
}

}  // namespace hcosim::rt
