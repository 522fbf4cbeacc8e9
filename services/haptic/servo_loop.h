// The haptic device service's servo loop, without DDS: each tick it reads
// the device and gives the HapticState to publish; it takes the sources'
// answers as they come, and says which it still waits for; then it renders
// each source's answer, or for a source whose answer is late its latest
// local model at the current position, sums them, passes the sum through
// the passivity controller and outputs it, clamped. A late answer, when it
// comes, is compared with what was rendered in its place. In lockstep the
// device and the sources at its rate form one Gauss-Seidel group: the
// force of step k answers the state of step k. services/haptic/main.cc
// wires it to its topics and does the waiting.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapters/device/device_config.h"
#include "idl/haptic.h"
#include "models/haptic/force_sum.h"
#include "models/haptic/passivity.h"
#include "services/runtime/service.h"
#include "services/runtime/stats.h"

namespace hcosim::services::haptic {

// Round trips from a HapticState's publication to the first force that
// answers it, over the last 4096 sequence numbers.
class RoundTrips {
 public:
  void sent(std::uint64_t seq, std::int64_t t) { at_[seq % at_.size()] = {seq, t}; }
  // True for the first answer to `seq`.
  bool answered(std::uint64_t seq, std::int64_t t);
  const runtime::Window& window() const { return window_; }

 private:
  struct Sent {
    std::uint64_t seq = ~0ull;
    std::int64_t t = -1;
  };
  std::vector<Sent> at_ = std::vector<Sent>(4096);
  runtime::Window window_{1 << 16};
};

// What the device rendered for each source at each recent tick, so that a
// late answer can be compared with the local model that stood in for it.
class Rendered {
 public:
  void put(const std::string& source, std::uint64_t seq, const Eigen::Vector3d& f);
  // What was rendered for `source` at tick `seq`, if still kept.
  std::optional<Eigen::Vector3d> at(const std::string& source, std::uint64_t seq) const;

 private:
  struct Entry {
    std::uint64_t seq = ~0ull;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
  };
  std::map<std::string, std::array<Entry, 256>> by_source_;
};

class ServoLoop {
 public:
  // The device `name` (HapticState.device) that `config` describes; in
  // lockstep the sources of `group` (those at its rate) answer each step
  // within it. Sources that fall silent or answer again are said on `log`.
  ServoLoop(const adapters::device::DeviceConfig& config, std::string name, std::vector<std::string> group,
            bool lockstep, std::FILE* log);

  // Begins a tick: reads the device and gives the state to publish, stamped
  // `stamp`; the round trip counts from here.
  HapticState begin(const runtime::Tick& tick, const StepStamp& stamp);
  // An answer that came during tick `step` (another device's is ignored).
  // In the Gauss-Seidel group, an answer of this step from a source outside
  // the group counts at the next step, as the Jacobi scheme has it.
  void take(const ForceFeedback& s, std::uint64_t step);
  // Outside the group, once the answers at hand are taken: the sources this
  // tick waits for, every fresh one but those whose latest answer is a
  // free-space model reaching the HIP (nothing of it near,
  // models::haptic::covers), which render exactly zero without waiting.
  void expect();
  // Whether an answer this tick waits for has not come.
  bool waiting() const;
  // Ends the tick: renders the sum of the sources' forces and outputs it.
  void end();

  bool gauss_seidel() const { return lockstep_ && !group_.empty(); }
  std::int64_t sent_ns() const { return sent_; }  // mono_ns when this tick's state was made
  std::uint64_t ticks() const { return seq_; }
  // The share of ticks every expected source answered in, of those that
  // expected one; the rendered-force error of late answers, p99, N.
  double in_tick_ratio() const { return with_sources_ ? double(in_tick_) / double(with_sources_) : 0; }
  double force_error_p99() const { return error_n_.percentile(0.99); }
  // The run's report as one JSON line (docs/haptic.md); the closing lines.
  std::string report_json() const;
  void report(std::FILE* out) const;

 private:
  void handle(const ForceFeedback& s);
  bool all_in(const std::vector<std::string>& want) const;

  std::string name_;
  std::vector<std::string> group_;
  bool lockstep_;
  std::FILE* log_;
  bool passivity_;
  double dt_, source_timeout_;
  models::haptic::PassivityController pc_;
  models::haptic::ForceSum sum_;
  std::unique_ptr<adapters::device::Device> device_;
  RoundTrips rtt_;
  Rendered rendered_;
  runtime::Window jitter_us_{1 << 16}, error_n_{1 << 12};
  Eigen::Vector3d applied_ = Eigen::Vector3d::Zero();
  adapters::device::Frame frame_;
  double now_ = 0;
  std::int64_t sent_ = 0;
  std::uint64_t seq_ = 0;
  std::uint64_t in_tick_ = 0, with_sources_ = 0;      // ticks every expected source answered in, of those expecting one
  std::uint64_t modelled_ = 0;                        // source-ticks rendered from a local model (the answer was late)
  std::uint64_t covered_ = 0;                         // source-ticks whose free-space model needed no answer
  double peak_ = 0;                                   // N, largest force rendered
  std::map<std::string, std::uint64_t> newest_;       // per source, the newest state answered
  std::map<std::string, std::int64_t> silent_since_;  // wall ns each silent source fell silent at
  // Sources that answered this tick's state, and those it waits for
  // (reused: no allocation per tick; names fit in a short string).
  std::vector<std::string> answered_, expected_;
  std::vector<ForceFeedback> deferred_;  // lockstep: this step's answers from outside the group
};

}  // namespace hcosim::services::haptic
