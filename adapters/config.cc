#include "adapters/config.h"

#include <algorithm>
#include <cmath>
#include <fstream>

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

}  // namespace

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

double config_number(const std::string& file, const YAML::Node& node, const std::string& key) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) throw config_error(file, node, "'" + key + "' must be a finite number");
    return v;
  } catch (const YAML::BadConversion&) {
    throw config_error(file, node, "'" + key + "' must be a number, not '" + node.Scalar() + "'");
  }
}

std::string config_text(const std::string& file, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) throw config_error(file, node, "'" + key + "' must be a string");
  return node.Scalar();
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

void check_keys(const std::string& file, const YAML::Node& map, const std::vector<std::string>& allowed) {
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string best;
    std::size_t best_d = 3;  // farther than this is not a typo
    for (const auto& a : allowed)
      if (std::size_t d = distance(key, a); d < best_d) best_d = d, best = a;
    std::string msg = "unknown key '" + key + "'";
    msg += best.empty() ? " (valid keys: " + join(allowed) + ")" : "; did you mean '" + best + "'?";
    throw config_error(file, kv.first, msg);
  }
}

YAML::Node load_yaml(const std::string& path) {
  if (!std::ifstream(path)) throw ConfigError(path + ": cannot be read");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                      ": YAML syntax error: " + e.msg);
  }
}

}  // namespace hcosim::adapters
