// hcosim bench: the suites and the report rows they produce.
#pragma once

#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace hcosim::cli {

using Value = std::variant<double, std::string>;

// One measured configuration. Metric names carry their unit (p99_us,
// ms_per_sim_s, rel_error, ...).
struct Row {
  std::string name;
  std::vector<std::pair<std::string, Value>> params;
  std::vector<std::pair<std::string, double>> metrics;
};

struct Context {
  bool quick = false;
  int domain = 0;
  std::filesystem::path out;  // where the report (and any plot) goes
};

struct Suite {
  const char* name;
  const char* what;
  std::function<std::vector<Row>(const Context&)> run;
};

inline void progress(const std::string& line) { std::cerr << "bench: " << line << std::endl; }

// Mass-spring integrators and MuJoCo on the same lattices: bench_massspring.cc.
Suite massspring_suite();

}  // namespace hcosim::cli
