// hcosim_haptic: the haptic device service. Each servo tick it reads the
// device and publishes the HapticState, then waits (up to `answer_wait`)
// for every source it expects to answer that state; it renders each
// source's answer, or for a source whose answer is late its latest local
// model at the current position, sums them, passes the sum through the
// passivity controller and outputs it, clamped. A late answer, when it
// comes, is compared with what was rendered in its place. In lockstep
// the device and the sources at its rate form one Gauss-Seidel group:
// the force of step k answers the state of step k. adapters::Config: docs/haptic.md.
#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "adapters/device/device_config.h"
#include "adapters/device/haptic_idl.h"
#include "adapters/json.h"
#include "models/haptic/force_sum.h"
#include "models/haptic/local_model.h"
#include "models/haptic/passivity.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

// Lockstep: how long a step waits for its group's answers before failing.
constexpr double kGroupWaitS = 10;

// Round trips from a HapticState's publication to the first force that
// answers it, over the last 4096 sequence numbers.
class RoundTrips {
 public:
  void sent(std::uint64_t seq, std::int64_t t) { at_[seq % at_.size()] = {seq, t}; }
  // True for the first answer to `seq`.
  bool answered(std::uint64_t seq, std::int64_t t) {
    Sent& s = at_[seq % at_.size()];
    if (s.seq != seq || s.t < 0) return false;
    window_.add((t - s.t) * 1e-3);
    s.t = -1;
    return true;
  }
  const Window& window() const { return window_; }

 private:
  struct Sent {
    std::uint64_t seq = ~0ull;
    std::int64_t t = -1;
  };
  std::vector<Sent> at_ = std::vector<Sent>(4096);
  Window window_{1 << 16};
};

// What the device rendered for each source at each recent tick, so that a
// late answer can be compared with the local model that stood in for it.
class Rendered {
 public:
  void put(const std::string& source, std::uint64_t seq, const Eigen::Vector3d& f) {
    auto& ring = by_source_[source];
    ring[seq % ring.size()] = {seq, f};
  }
  // What was rendered for `source` at tick `seq`, if still kept.
  std::optional<Eigen::Vector3d> at(const std::string& source, std::uint64_t seq) const {
    const auto it = by_source_.find(source);
    if (it == by_source_.end()) return std::nullopt;
    const Entry& e = it->second[seq % it->second.size()];
    if (e.seq != seq) return std::nullopt;
    return e.force;
  }

 private:
  struct Entry {
    std::uint64_t seq = ~0ull;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
  };
  std::map<std::string, std::array<Entry, 256>> by_source_;
};

int run(const Options& options) {
  Service svc(options);
  const adapters::device::DeviceConfig config = adapters::device::device_config(svc.params(), svc.options().rate_hz);
  const bool passivity = config.passivity;
  const double dt = 1 / config.spec.servo_hz;
  models::haptic::PassivityController pc(dt, config.max_damping, config.reservoir);
  models::haptic::ForceSum sum(config.source_timeout);
  const std::unique_ptr<adapters::device::Device> dev = adapters::device::make_device(config);
  adapters::device::Device& omni = *dev;
  const double answer_wait = config.answer_wait;
  const std::string& report = config.report;

  // In real time a source is waited for once it has answered and while it
  // stays fresh (a service still building its model is not yet a source;
  // one that died drops out after source_timeout). In lockstep the sources
  // the deployment names at this rate are the Gauss-Seidel group, waited
  // for from the first step.
  const std::string name = svc.options().name;
  std::vector<std::string> group;
  for (const adapters::ForceSource& fs : adapters::force_sources(svc.deployment(), name))
    if (fs.rate_hz == svc.options().rate_hz) group.push_back(fs.object);
  const bool lockstep = svc.options().mode == adapters::Mode::kLockstep;

  Writer<HapticState> out(svc.participant());
  Reader<ForceFeedback> in = svc.reader<ForceFeedback>();
  RoundTrips rtt;
  Rendered rendered;
  Window jitter_us(1 << 16), error_n(1 << 12);
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();
  std::uint64_t seq = 0;
  std::uint64_t in_tick = 0, with_sources = 0;       // ticks every expected source answered in, of those expecting one
  std::uint64_t modelled = 0;                        // source-ticks rendered from a local model (the answer was late)
  std::uint64_t covered = 0;                         // source-ticks whose free-space model needed no answer
  double peak = 0;                                   // N, largest force rendered
  std::map<std::string, std::uint64_t> newest;       // per source, the newest state answered
  std::map<std::string, std::int64_t> silent_since;  // wall ns each silent source fell silent at
  // Sources that answered this tick's state, and those it waits for
  // (reused: no allocation per tick; names fit in a short string).
  std::vector<std::string> answered, expected;
  std::vector<ForceFeedback> deferred;  // lockstep: this step's answers from outside the group
  const auto has = [](const std::vector<std::string>& v, const std::string& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  const auto handle = [&](const ForceFeedback& s, double now) {
    const std::string from = s.source().to_string();
    const models::haptic::LocalModel model = adapters::device::local_model(s);
    // The round trip and the rendered-force error are those of answers the
    // device waits for: a free-space one is rendered without waiting,
    // whenever it comes, and is exact.
    const bool free = models::haptic::covers(model, model.position);
    if (!free) rtt.answered(s.answers_seq(), mono_ns());
    if (s.answers_seq() == seq) {
      if (!has(answered, from)) answered.push_back(from);
    }
    // A late answer: what the user felt in its place, against it.
    else if (const auto r = rendered.at(from, s.answers_seq()); r && !free)
      error_n.add((adapters::device::from_idl(s.force()) - *r).norm());
    auto [it, fresh] = newest.try_emplace(from, s.answers_seq());
    if (!fresh && s.answers_seq() < it->second) return;  // an older answer overtaken by a newer one
    it->second = s.answers_seq();
    sum.set(from, model, now);
  };
  const auto mine = [&](const ForceFeedback& s) { return s.device().to_string() == name; };
  const auto all_in = [&](const std::vector<std::string>& want) {
    return std::all_of(want.begin(), want.end(), [&](const std::string& x) { return has(answered, x); });
  };
  const int status = svc.run([&](const Tick& tick) {
    jitter_us.add(tick.late_us);
    const adapters::device::Frame f = omni.begin_frame();
    const double now = tick.sim_time_ns * 1e-9;
    HapticState hs = adapters::device::haptic_state(name, seq, svc.stamp(tick), f, applied);
    const std::int64_t sent = mono_ns();
    rtt.sent(seq, sent);
    out.write(hs);
    answered.clear();
    expected.clear();
    const bool gauss_seidel = lockstep && !group.empty();
    if (gauss_seidel) {
      // Gauss-Seidel: this step's state went out; the group answers it
      // within the step, and the force rendered now is theirs.
      for (const ForceFeedback& s : deferred) handle(s, now);
      deferred.clear();
      const std::int64_t deadline = sent + std::int64_t(kGroupWaitS * 1e9);
      for (;;) {
        in.take_before(tick.step + 1, [&](const ForceFeedback& s) {
          if (!mine(s)) return;
          if (s.stamp().step() == tick.step && !has(group, s.source().to_string()))
            deferred.push_back(s);
          else
            handle(s, now);
        });
        if (all_in(group) || stop_requested()) break;
        if (mono_ns() > deadline)
          throw std::runtime_error(name + ": step " + std::to_string(tick.step) +
                                   ": the sources of its group did not answer in " + std::to_string(int(kGroupWaitS)) +
                                   " s");
        in.wait(std::chrono::milliseconds(100));
      }
    } else {
      const auto take = [&] {
        svc.take(in, tick, [&](const ForceFeedback& s) {
          if (mine(s)) handle(s, now);
        });
      };
      take();
      // A source whose latest answer is a free-space model reaching the
      // HIP (nothing of it near, models::haptic::covers) renders exactly zero: no
      // newer answer is needed, and none is waited for.
      sum.expire(now);
      for (const auto& [from, last] : newest) {
        if (!sum.has(from)) continue;
        if (double(seq - last) * dt <= models::haptic::kFreeHorizonS && sum.covers(from, f.position))
          ++covered;
        else
          expected.push_back(from);
      }
      // In lockstep outside a group, this tick's answers belong to the next
      // tick: no wait.
      const std::int64_t deadline = sent + std::int64_t(lockstep ? 0 : answer_wait * 1e9);
      while (!all_in(expected) && mono_ns() < deadline && in.wait(std::chrono::nanoseconds(deadline - mono_ns())))
        take();
    }
    const Eigen::Vector3d env = sum.total(now, f.position);
    for (const auto& [from, last] : newest) {
      // A source that falls silent (its host gone) drops out with its force,
      // which is zero, not its last; said when it does and when it is back.
      const bool live = sum.has(from);
      const auto silent = silent_since.find(from);
      if (!live && silent == silent_since.end()) {
        silent_since.emplace(from, wall_ns());
        std::printf("%s: source '%s' fell silent (no answer for %.3g s): its force is zero until it answers again\n",
                    name.c_str(), from.c_str(), config.source_timeout);
        std::fflush(stdout);
      } else if (live && silent != silent_since.end()) {
        std::printf("%s: source '%s' answers again after %.2f s silent (wall time %.3f s)\n", name.c_str(),
                    from.c_str(), (wall_ns() - silent->second) * 1e-9, wall_ns() * 1e-9);
        std::fflush(stdout);
        silent_since.erase(silent);
      }
      if (!live) continue;
      rendered.put(from, seq, sum.force_of(from));
      if (last != seq && (gauss_seidel || has(expected, from))) ++modelled;
    }
    const std::vector<std::string>& waited = gauss_seidel ? group : expected;
    if (!waited.empty()) ++with_sources, in_tick += all_in(waited);
    peak = std::max(peak, env.norm());
    applied = omni.end_frame(passivity ? pc.filter(env, f.velocity, applied) : env);
    if (seq % 1000 == 999)
      svc.set_haptic_figures(with_sources ? double(in_tick) / double(with_sources) : 0, error_n.percentile(0.99));
    ++seq;
  });
  const Window& w = rtt.window();
  const double in_tick_ratio = with_sources ? double(in_tick) / double(with_sources) : 0;
  svc.set_haptic_figures(in_tick_ratio, error_n.percentile(0.99));
  if (!report.empty()) {
    // Percentiles of no sample are NaN (no late answer: no error), which
    // JSON writes as null.
    adapters::Json j;
    j["ticks"] = std::uint64_t(seq);
    j["answered"] = std::uint64_t(w.size());
    j["p50_us"] = w.percentile(0.5);
    j["p99_us"] = w.percentile(0.99);
    j["on_time_ratio"] = in_tick_ratio;
    j["jitter_p50_us"] = jitter_us.percentile(0.5);
    j["jitter_p99_us"] = jitter_us.percentile(0.99);
    j["modelled"] = std::uint64_t(modelled);
    j["covered"] = std::uint64_t(covered);
    j["late_answers"] = std::uint64_t(error_n.size());
    j["force_error_p99_n"] = error_n.percentile(0.99);
    j["peak_force_n"] = peak;
    j["saturated"] = std::uint64_t(omni.saturated());
    std::ofstream r(report);
    r << adapters::json_line(j) << "\n";
    if (!r) throw std::runtime_error("cannot write " + report);
  }
  std::printf(
      "%s: %llu ticks, %zu answered, round trip p50 %.0f us p99 %.0f us, %.4f on time, %llu saturated, "
      "%llu sources timed out, %.3g J dissipated by the passivity controller\n",
      name.c_str(), static_cast<unsigned long long>(omni.frames()), w.size(), w.percentile(0.5), w.percentile(0.99),
      in_tick_ratio, static_cast<unsigned long long>(omni.saturated()), static_cast<unsigned long long>(sum.expired()),
      pc.dissipated());
  std::printf(
      "%s: wake-up jitter p50 %.0f us p99 %.0f us; %llu source-ticks rendered from a local model, "
      "%llu from a free-space one (nothing near); %zu late answers, rendered-force error p99 %.4f N of a "
      "%.3f N peak\n",
      name.c_str(), jitter_us.percentile(0.5), jitter_us.percentile(0.99), static_cast<unsigned long long>(modelled),
      static_cast<unsigned long long>(covered), error_n.size(), error_n.percentile(0.99), peak);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_haptic",
                      "the haptic device service: reads the device, renders the sum of its sources' forces", argc, argv,
                      run);
}
