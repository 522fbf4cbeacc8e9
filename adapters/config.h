// Reading YAML configuration files (deployments and their params, virtual-
// user scripts, camera intrinsics) with errors that name the file, line
// and column. Every configuration file of hcosim is read through Config.
#pragma once

#include <array>
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

// "FILE:LINE:COL: what" for a node.
ConfigError config_error(const std::string& file, const YAML::Node& node, const std::string& what);

// ", "-joined items, for messages.
std::string join(const std::vector<std::string>& items);

// One map of a configuration file, read key by key: each reader returns
// its fallback when the key is absent and throws a ConfigError at the
// value's FILE:LINE:COL when it is malformed. An unknown key is named with
// the closest valid one ("did you mean").
class Config {
 public:
  // `node` of `file`: a map, or absent (every key then takes its fallback).
  Config(std::string file, YAML::Node node);
  // The root map of the file at `path`; `what` names its kind in the error
  // when the root is not a map ("a deployment").
  static Config load(const std::string& path, const std::string& what);
  // The root map of YAML `text`, read as the file `file`.
  static Config parse(const std::string& text, const std::string& file, const std::string& what);

  bool has(const std::string& key) const { return node_ && node_.IsMap() && node_[key]; }
  // A finite number in [lo, hi].
  double number(const std::string& key, double fallback, double lo, double hi) const;
  // A whole number in [lo, hi].
  int whole(const std::string& key, int fallback, int lo, int hi) const;
  // A string that is one of `allowed`.
  std::string text(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed) const;
  // A switch: on or off, or YAML's true or false (what a file written back
  // by a YAML library says).
  bool on(const std::string& key, bool fallback) const;
  // Any string.
  std::string string(const std::string& key, const std::string& fallback) const;
  // A file path, relative paths taken from this file's folder; "" when
  // absent. The file must exist.
  std::string path(const std::string& key) const;
  // The path of a file to write, relative paths taken from this file's
  // folder; "" when absent.
  std::string output_path(const std::string& key) const;
  // [x, y, z] of finite numbers.
  std::array<double, 3> vec3(const std::string& key, const std::array<double, 3>& fallback) const;
  // The numbers of a list, each in [lo, hi]; empty when absent.
  std::vector<double> numbers(const std::string& key, double lo, double hi) const;
  // The maps of a list, each read as a Config of its own; empty when absent.
  std::vector<Config> list(const std::string& key) const;
  // The map at `key` (an empty one when absent).
  Config map(const std::string& key) const;

  // Throws unless every key of `keys` is present: "`what` is missing
  // required key 'K'", at this map.
  void require(const std::vector<std::string>& keys, const std::string& what) const;
  // Throws at the first key outside `allowed`, naming the closest valid one.
  void allow_only(const std::vector<std::string>& allowed) const;
  // Throws a ConfigError at the value of `key` (at this map when absent).
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  // "FILE:LINE:COL" of the value of `key` (of this map when absent or "").
  std::string where(const std::string& key = "") const;

  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }

 private:
  std::string file_;
  YAML::Node node_;
};

}  // namespace hcosim::adapters
