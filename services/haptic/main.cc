// hcosim_haptic: the haptic device service. Each servo tick it reads the
// device and publishes the HapticState, takes the ForceFeedback of every
// source (waiting up to `answer_wait` for the answers to this tick), sums
// each source's latest, passes the sum through the passivity controller
// and outputs it, clamped. Params: docs/haptic.md.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>

#include "device/haptic_idl.h"
#include "device/replay.h"
#include "device/script_yaml.h"
#include "device/simulated_omni.h"
#include "haptic/force_sum.h"
#include "haptic/passivity.h"
#include "service.h"

using namespace hcosim;
using namespace hcosim::rt;

namespace {

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

int run(int argc, char** argv) {
  Service svc(parse_options(argc, argv));
  const Params& p = svc.params();
  p.allow_only({"device", "replay", "script", "passivity", "source_timeout", "max_damping", "reservoir", "hand_stiffness", "hand_damping",
                "centre", "answer_wait", "sources", "report"});
  const bool replay = p.text("device", "simulated", {"simulated", "replay"}) == "replay";
  const std::string source = p.path(replay ? "replay" : "script");
  if (source.empty())
    throw ConfigError(std::string("hcosim_haptic: params.") + (replay ? "replay (a recorded trajectory, CSV)" : "script (a virtual-user script)") +
                      " is required; docs/haptic.md");
  haptic::OmniSpec spec;
  const auto c = p.vec3("centre", {0, 0, 0});
  spec.centre = {c[0], c[1], c[2]};
  spec.servo_hz = svc.options().rate_hz;
  haptic::Hand hand;
  hand.stiffness = p.number("hand_stiffness", hand.stiffness, 1, 1e4);
  hand.damping = p.number("hand_damping", hand.damping, 0, 1e3);
  const bool passivity = p.text("passivity", "on", {"on", "off"}) == "on";
  const double dt = 1 / spec.servo_hz;
  haptic::PassivityController pc(dt, p.number("max_damping", 20, 1e-3, 1e3), p.number("reservoir", 1e-4, 1e-9, 10));
  haptic::ForceSum sum(p.number("source_timeout", 0.05, 1e-3, 10));
  std::unique_ptr<device::Device> dev;
  if (replay) dev = std::make_unique<device::Replay>(spec, device::load_trajectory(source));
  else dev = std::make_unique<device::SimulatedOmni>(spec, hand, device::load_script(source));
  device::Device& omni = *dev;
  // Waiting for this tick's answers gives forces computed from this tick's
  // position; `sources` says how many answers to wait for.
  const double answer_wait = p.number("answer_wait", 0, 0, 0.9 / spec.servo_hz);
  const std::size_t sources = std::size_t(p.number("sources", 1, 1, 64));
  const std::string report = p.output_path("report");

  Writer<HapticState> out(svc.participant());
  Reader<ForceFeedback> in = svc.reader<ForceFeedback>();
  const std::string name = svc.options().name;
  RoundTrips rtt;
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();
  std::uint64_t seq = 0;
  std::uint64_t on_time = 0, with_sources = 0;  // ticks answered in time, of those with every source matched
  std::vector<std::string> answered;            // sources that answered this tick (reused: no allocation per tick)
  const int status = svc.run([&](const Tick& tick) {
    const device::Frame f = omni.begin_frame();
    const double now = tick.sim_time_ns * 1e-9;
    HapticState hs = device::haptic_state(name, seq, svc.stamp(tick), f, applied);
    const std::int64_t sent = mono_ns();
    rtt.sent(seq, sent);
    out.write(hs);
    answered.clear();
    auto take = [&] {
      svc.take(in, tick, [&](const ForceFeedback& s) {
        if (s.device().to_string() != name) return;
        rtt.answered(s.answers_seq(), mono_ns());
        const std::string from = s.source().to_string();
        sum.set(from, device::from_idl(s.force()), now);
        if (s.answers_seq() == seq && std::find(answered.begin(), answered.end(), from) == answered.end())
          answered.push_back(from);
      });
    };
    take();
    // In lockstep this tick's answers belong to the next tick: no wait.
    const std::int64_t deadline = sent + std::int64_t(svc.options().mode == Mode::kLockstep ? 0 : answer_wait * 1e9);
    while (answered.size() < sources && mono_ns() < deadline && in.wait(std::chrono::nanoseconds(deadline - mono_ns())))
      take();
    if (in.matched() >= int(sources)) ++with_sources, on_time += answered.size() >= sources;
    const Eigen::Vector3d env = sum.total(now);
    applied = omni.end_frame(passivity ? pc.filter(env, f.velocity, applied) : env);
    ++seq;
  });
  const Window& w = rtt.window();
  const double on_time_ratio = with_sources ? double(on_time) / double(with_sources) : 0;
  if (!report.empty()) {
    std::ofstream r(report);
    r << "{\"ticks\":" << seq << ",\"answered\":" << w.size() << ",\"p50_us\":" << w.percentile(0.5)
      << ",\"p99_us\":" << w.percentile(0.99) << ",\"on_time_ratio\":" << on_time_ratio
      << ",\"saturated\":" << omni.saturated() << "}\n";
    if (!r) throw std::runtime_error("cannot write " + report);
  }
  std::printf("%s: %llu ticks, %zu answered, round trip p50 %.0f us p99 %.0f us, %.4f on time, %llu saturated, "
              "%llu sources timed out, %.3g J dissipated by the passivity controller\n",
              name.c_str(), static_cast<unsigned long long>(omni.frames()), w.size(), w.percentile(0.5),
              w.percentile(0.99), on_time_ratio, static_cast<unsigned long long>(omni.saturated()),
              static_cast<unsigned long long>(sum.expired()), pc.dissipated());
  return status;
}

}  // namespace

int main(int argc, char** argv) { return guarded_main("hcosim_haptic", [&] { return run(argc, argv); }); }
