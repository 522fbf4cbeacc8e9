// Reading YAML configuration files (deployments, virtual-user scripts) with
// errors that name the file, line and column.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace hcosim::adapters {

// A configuration problem, with its message already as "FILE:LINE:COL: what".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "FILE:LINE:COL" of a node (1-based line and column); "FILE" for a node
// the program made.
std::string config_where(const std::string& file, const YAML::Node& node);

// "FILE:LINE:COL: what" for a node (1-based line and column).
ConfigError config_error(const std::string& file, const YAML::Node& node, const std::string& what);

// Throws unless every key of `map` is in `allowed`; names the closest valid key.
void check_keys(const std::string& file, const YAML::Node& map, const std::vector<std::string>& allowed);

// The file's YAML; a missing file or a syntax error is a ConfigError.
YAML::Node load_yaml(const std::string& path);

// `node` as a finite number or a string; `key` names it in the error.
double config_number(const std::string& file, const YAML::Node& node, const std::string& key);
std::string config_text(const std::string& file, const YAML::Node& node, const std::string& key);

// ", "-joined items, for messages.
std::string join(const std::vector<std::string>& items);

}  // namespace hcosim::adapters
