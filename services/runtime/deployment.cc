#include "deployment.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <set>

#include "participant.h"

namespace hcosim::rt {
namespace {

// Edit distance between two keys, for "did you mean" hints.
std::size_t distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

double number(const std::string& file, const YAML::Node& node, const std::string& key) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) throw config_error(file, node, "'" + key + "' must be a finite number");
    return v;
  } catch (const YAML::BadConversion&) {
    throw config_error(file, node, "'" + key + "' must be a number, not '" + node.Scalar() + "'");
  }
}

std::string text(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) throw config_error(file, node, "'" + key + "' must be a string");
  return node.Scalar();
}

ServiceSpec parse_service(const std::string& file, const YAML::Node& node) {
  if (!node.IsMap()) throw config_error(file, node, "each service must be a map with name, kind and rate");
  check_keys(file, node, {"name", "kind", "rate", "params"});
  ServiceSpec s;
  s.line = node.Mark().line + 1;
  for (const char* key : {"name", "kind", "rate"})
    if (!node[key]) throw config_error(file, node, std::string("service is missing required key '") + key + "'");
  s.name = text(file, node["name"], "name");
  if (!std::regex_match(s.name, std::regex("[a-z][a-z0-9_]{0,30}")))
    throw config_error(file, node["name"],
                       "service name '" + s.name + "' must be 1 to 31 of a-z, 0-9, _ and start with a letter");
  s.kind = text(file, node["kind"], "kind");
  if (!std::regex_match(s.kind, std::regex("[a-z][a-z0-9_]*")))
    throw config_error(file, node["kind"], "service kind '" + s.kind + "' must be a-z, 0-9 and _");
  s.rate_hz = number(file, node["rate"], "rate");
  if (s.rate_hz <= 0 || s.rate_hz > 1e5)
    throw config_error(file, node["rate"], "'rate' must be in (0, 100000] Hz");
  s.params = node["params"] ? node["params"] : YAML::Node(YAML::NodeType::Map);
  if (!s.params.IsMap()) throw config_error(file, node["params"], "'params' must be a map");
  return s;
}

}  // namespace

ConfigError config_error(const std::string& file, const YAML::Node& node, const std::string& what) {
  const auto m = node.Mark();
  return ConfigError(file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1) + ": " + what);
}

void check_keys(const std::string& file, const YAML::Node& map, const std::vector<std::string>& allowed) {
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string best;
    std::size_t best_d = 3;  // farther than this is not a typo
    for (const auto& a : allowed)
      if (std::size_t d = distance(key, a); d < best_d) best_d = d, best = a;
    std::string msg = "unknown key '" + key + "'";
    msg += best.empty() ? " (valid keys: " + list(allowed) + ")" : "; did you mean '" + best + "'?";
    throw config_error(file, kv.first, msg);
  }
}

const char* to_string(Mode m) { return m == Mode::kLockstep ? "lockstep" : "realtime"; }

Mode parse_mode(const std::string& s) {
  if (s == "realtime") return Mode::kRealtime;
  if (s == "lockstep") return Mode::kLockstep;
  throw std::invalid_argument("mode must be 'realtime' or 'lockstep', not '" + s + "'");
}

Deployment load_deployment(const std::string& path) {
  if (!std::ifstream(path)) throw ConfigError(path + ": cannot be read");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                      ": YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) throw ConfigError(path + ":1:1: a deployment must be a YAML map");
  check_keys(path, root, {"domain", "mode", "step", "duration", "services"});

  Deployment d;
  d.file = path;
  if (auto n = root["domain"]) {
    const double v = number(path, n, "domain");
    if (v != std::floor(v) || v < 0 || v > kMaxDomain)
      throw config_error(path, n, "'domain' must be a whole number in 0.." + std::to_string(kMaxDomain));
    d.domain = static_cast<int>(v);
  }
  if (auto n = root["mode"]) {
    try {
      d.mode = parse_mode(text(path, n, "mode"));
    } catch (const std::invalid_argument& e) {
      throw config_error(path, n, e.what());
    }
  }
  if (auto n = root["step"]) {
    d.step_s = number(path, n, "step");
    if (d.step_s < 1e-6 || d.step_s > 1) throw config_error(path, n, "'step' must be in [1e-6, 1] s");
  }
  if (auto n = root["duration"]) {
    d.duration_s = number(path, n, "duration");
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
      d.services.push_back(std::move(spec));
    }
  }
  return d;
}

Params::Params(std::string file, YAML::Node node) : file_(std::move(file)), node_(std::move(node)) {}

double Params::number(const std::string& key, double fallback, double lo, double hi) const {
  if (!node_ || !node_[key]) return fallback;
  const YAML::Node n = node_[key];
  const double v = rt::number(file_, n, key);
  if (v < lo || v > hi)
    throw config_error(file_, n, "'" + key + "' = " + n.Scalar() + " is outside [" + std::to_string(lo) + ", " +
                                     std::to_string(hi) + "]");
  return v;
}

std::string Params::text(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const {
  if (!node_ || !node_[key]) return fallback;
  const std::string v = rt::text(file_, node_[key], key);
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
    throw config_error(file_, node_[key], "'" + key + "' must be one of " + list(allowed) + ", not '" + v + "'");
  return v;
}

void Params::allow_only(const std::vector<std::string>& allowed) const {
  if (node_ && node_.IsMap()) check_keys(file_, node_, allowed);
}

}  // namespace hcosim::rt
