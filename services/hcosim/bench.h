// hcosim bench: the suites and the report rows they produce.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "stats.h"

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

// The haptic device's closed loop, the stiff-wall rig: bench_haptic.cc.
Suite haptic_suite();

// The hybrid deformable model's parts and pipeline: bench_hybrid.cc.
Suite hybrid_suite();

// The rigid model against eq 2 and MuJoCo, and its step cost: bench_rigid.cc.
Suite rigid_suite();

// Marker detection and pose against ground truth and ArUco: bench_tracking.cc.
Suite tracking_suite();

// The AR view's frame against OpenCV drawing the same triangles: bench_arview.cc.
Suite arview_suite();

// 1 kHz HapticState -> ForceFeedback round trips, us (bench.cc).
struct Rtt {
  rt::Window us{1 << 20};
  std::uint64_t sent = 0, lost = 0;
};

// A peer process answering HapticState with ForceFeedback: `impl` "bare"
// (Fast DDS alone) or "hcosim" (the service runtime).
pid_t start_peer(const std::string& impl, int domain, double seconds);
void stop_peer(pid_t pid);

// Round trips against a bare Fast DDS peer for `seconds`.
Rtt bare_rtt(int domain, double seconds);

}  // namespace hcosim::cli
