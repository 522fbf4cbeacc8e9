// Samples of the topic contract as the services' loops take them, and what
// a report writes to a FILE*, for tests that drive a loop without DDS.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <Eigen/Core>

#include "idl/haptic.h"

namespace hcosim::tests {

// The stamp of base step `step`, steps of `step_ns` apart.
inline StepStamp stamp(std::uint64_t step, std::int64_t step_ns = 1'000'000) {
  StepStamp s;
  s.step(step);
  s.sim_time_ns(std::int64_t(step) * step_ns);
  return s;
}

// Device `device`'s state `seq` with the stylus at `at` (m, world), still.
inline HapticState haptic_state(std::uint64_t seq, const Eigen::Vector3d& at, const std::string& device = "omni") {
  HapticState s;
  s.device(device);
  s.seq(seq);
  s.device_time_s(double(seq) * 1e-3);
  s.position().x(at.x()), s.position().y(at.y()), s.position().z(at.z());
  s.orientation().w(1.0);
  return s;
}

// What `write(out)` writes to the FILE* it is given.
template <class F>
std::string written(F write) {
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  write(out);
  std::fclose(out);
  const std::string s(text, size);
  std::free(text);
  return s;
}

}  // namespace hcosim::tests
