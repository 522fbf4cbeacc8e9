#include "adapters/config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace hcosim::adapters {
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

// A bound as a person writes it: 0.001, 100000, inf.
std::string bound(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double number_of(const std::string& file, const YAML::Node& node, const std::string& key) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) throw config_error(file, node, "'" + key + "' must be a finite number");
    return v;
  } catch (const YAML::BadConversion&) {
    throw config_error(file, node, "'" + key + "' must be a number, not '" + node.Scalar() + "'");
  }
}

std::string text_of(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) throw config_error(file, node, "'" + key + "' must be a string");
  return node.Scalar();
}

}  // namespace

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string config_where(const std::string& file, const YAML::Node& node) {
  const auto m = node.Mark();
  // A node made by the program (a default, or a scene's part) has no place in the file.
  if (m.is_null()) return file;
  return file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

ConfigError config_error(const std::string& file, const YAML::Node& node, const std::string& what) {
  return ConfigError(config_where(file, node) + ": " + what);
}

Config::Config(std::string file, YAML::Node node) : file_(std::move(file)), node_(std::move(node)) {}

Config Config::parse(const std::string& text, const std::string& file, const std::string& what) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(file + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                      ": YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) throw ConfigError(file + ":1:1: " + what + " must be a YAML map");
  return Config(file, root);
}

Config Config::load(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), path, what);
}

double Config::number(const std::string& key, double fallback, double lo, double hi) const {
  if (!has(key)) return fallback;
  const YAML::Node n = node_[key];
  const double v = number_of(file_, n, key);
  if (v < lo || v > hi)
    throw config_error(file_, n,
                       "'" + key + "' = " + n.Scalar() + " is outside [" + bound(lo) + ", " + bound(hi) + "]");
  return v;
}

int Config::whole(const std::string& key, int fallback, int lo, int hi) const {
  if (!has(key)) return fallback;
  const YAML::Node n = node_[key];
  const double v = number_of(file_, n, key);
  if (v != std::floor(v) || v < lo || v > hi)
    throw config_error(file_, n,
                       "'" + key + "' must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                           ", not " + n.Scalar());
  return int(v);
}

std::string Config::text(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const {
  if (!has(key)) return fallback;
  const std::string v = text_of(file_, node_[key], key);
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
    throw config_error(file_, node_[key], "'" + key + "' must be one of " + join(allowed) + ", not '" + v + "'");
  return v;
}

bool Config::on(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  const std::string v = text_of(file_, node_[key], key);
  if (v == "on" || v == "true") return true;
  if (v == "off" || v == "false") return false;
  throw config_error(file_, node_[key], "'" + key + "' must be on or off (or true or false), not '" + v + "'");
}

std::string Config::string(const std::string& key, const std::string& fallback) const {
  return has(key) ? text_of(file_, node_[key], key) : fallback;
}

std::string Config::path(const std::string& key) const {
  if (!has(key)) return "";
  const std::string p = output_path(key);
  if (!fs::exists(p)) throw config_error(file_, node_[key], "'" + key + "': no file " + p);
  return p;
}

std::string Config::output_path(const std::string& key) const {
  if (!has(key)) return "";
  fs::path p = text_of(file_, node_[key], key);
  if (p.is_relative()) p = fs::path(file_).parent_path() / p;
  return p.string();
}

std::array<double, 3> Config::vec3(const std::string& key, const std::array<double, 3>& fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node n = node_[key];
  if (!n.IsSequence() || n.size() != 3) throw config_error(file_, n, "'" + key + "' must be [x, y, z]");
  return {number_of(file_, n[0], key), number_of(file_, n[1], key), number_of(file_, n[2], key)};
}

std::vector<double> Config::numbers(const std::string& key, double lo, double hi) const {
  std::vector<double> out;
  if (!has(key)) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) throw config_error(file_, n, "'" + key + "' must be a list of numbers");
  for (const YAML::Node& item : n) {
    const double v = number_of(file_, item, key);
    if (v < lo || v > hi)
      throw config_error(
          file_, item,
          "an entry of '" + key + "', " + item.Scalar() + ", is outside [" + bound(lo) + ", " + bound(hi) + "]");
    out.push_back(v);
  }
  return out;
}

std::vector<Config> Config::list(const std::string& key) const {
  std::vector<Config> out;
  if (!has(key)) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) throw config_error(file_, n, "'" + key + "' must be a list");
  for (const YAML::Node& item : n) {
    if (!item.IsMap()) throw config_error(file_, item, "each entry of '" + key + "' must be a map of keys");
    out.emplace_back(file_, item);
  }
  return out;
}

Config Config::map(const std::string& key) const {
  if (!has(key)) return Config(file_, YAML::Node(YAML::NodeType::Map));
  const YAML::Node n = node_[key];
  if (!n.IsMap()) throw config_error(file_, n, "'" + key + "' must be a map of keys");
  return Config(file_, n);
}

void Config::require(const std::vector<std::string>& keys, const std::string& what) const {
  for (const auto& k : keys)
    if (!has(k)) throw config_error(file_, node_, what + " is missing required key '" + k + "'");
}

void Config::allow_only(const std::vector<std::string>& allowed) const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string best;
    std::size_t best_d = 3;  // farther than this is not a typo
    for (const auto& a : allowed)
      if (std::size_t d = distance(key, a); d < best_d) best_d = d, best = a;
    std::string msg = "unknown key '" + key + "'";
    msg += best.empty() ? " (valid keys: " + join(allowed) + ")" : "; did you mean '" + best + "'?";
    throw config_error(file_, kv.first, msg);
  }
}

void Config::fail(const std::string& key, const std::string& what) const {
  throw config_error(file_, has(key) ? node_[key] : node_, what);
}

std::string Config::where(const std::string& key) const {
  return config_where(file_, !key.empty() && has(key) ? node_[key] : node_);
}

}  // namespace hcosim::adapters
