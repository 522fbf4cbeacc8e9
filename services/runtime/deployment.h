// The deployment file: which services run, on which domain, in which time mode.
// Every key, unit and default: docs/deployment.md.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "config.h"

namespace hcosim::rt {

// Configuration errors name FILE:LINE:COL (adapters/config.h).
using hcosim::check_keys;
using hcosim::config_error;
using hcosim::ConfigError;

enum class Mode { kRealtime, kLockstep };
const char* to_string(Mode m);
Mode parse_mode(const std::string& s);  // throws std::invalid_argument

// One service entry of the deployment.
struct ServiceSpec {
  std::string name;    // unique, [a-z0-9_], at most 31 characters
  std::string kind;    // executable build/bin/hcosim_<kind>
  double rate_hz = 0;  // step rate, Hz, > 0
  YAML::Node params;   // kind-specific; checked by the service itself
  int line = 0;        // 1-based line of the entry in the file
};

struct Deployment {
  std::string file;
  int domain = 0;           // DDS domain id, 0..232
  Mode mode = Mode::kRealtime;
  double step_s = 0.001;    // base step, s: lockstep tick length
  double duration_s = 0;    // s of simulated time (lockstep) or wall time; 0 = until stopped
  std::vector<ServiceSpec> services;
};

// Reads and validates a whole deployment file. Throws ConfigError on the
// first problem, naming FILE:LINE:COL.
Deployment load_deployment(const std::string& path);

// Kind-specific parameters of one service, read with located errors.
class Params {
 public:
  Params(std::string file, YAML::Node node);
  // The number at `key`, or `fallback` when absent; must lie in [lo, hi].
  double number(const std::string& key, double fallback, double lo, double hi) const;
  // The string at `key`, or `fallback` when absent; must be one of `allowed`.
  std::string text(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed) const;
  // The string at `key`, or `fallback` when absent; any value.
  std::string string(const std::string& key, const std::string& fallback) const;
  // The file path at `key`, relative paths taken from the deployment
  // file's folder; "" when absent. The file must exist.
  std::string path(const std::string& key) const;
  // The path of a file to write at `key`, relative paths taken from the
  // deployment file's folder; "" when absent.
  std::string output_path(const std::string& key) const;
  // The [x, y, z] at `key`, or `fallback` when absent.
  std::array<double, 3> vec3(const std::string& key, const std::array<double, 3>& fallback) const;
  // The maps of the list at `key`, each read as Params of its own; empty
  // when absent. Throws unless it is a list of maps.
  std::vector<Params> list(const std::string& key) const;
  // Throws a ConfigError at this node naming `what`.
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  // Throws if a key outside `allowed` is present.
  void allow_only(const std::vector<std::string>& allowed) const;

 private:
  std::string file_;
  YAML::Node node_;
};

}  // namespace hcosim::rt
