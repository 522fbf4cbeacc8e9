// hcosim_haptic: the haptic device service. Each servo tick it reads the
// device, sums the latest ForceFeedback of every source, passes it through
// the passivity controller, outputs it (clamped), and publishes the
// HapticState. Params (docs/haptic.md): script, passivity, source_timeout,
// max_damping, reservoir, hand_stiffness, hand_damping, centre.
#include <cstdio>
#include <vector>

#include "device/haptic_idl.h"
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
  void answered(std::uint64_t seq, std::int64_t t) {
    Sent& s = at_[seq % at_.size()];
    if (s.seq != seq || s.t < 0) return;
    window_.add((t - s.t) * 1e-3);
    s.t = -1;  // the first answer only
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
  p.allow_only({"script", "passivity", "source_timeout", "max_damping", "reservoir", "hand_stiffness", "hand_damping",
                "centre"});
  const std::string script = p.path("script");
  if (script.empty()) throw ConfigError("hcosim_haptic: params.script is required (a virtual-user script, docs/haptic.md)");
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
  device::SimulatedOmni omni(spec, hand, device::load_script(script));

  Writer<HapticState> out(svc.participant());
  Reader<ForceFeedback> in = svc.reader<ForceFeedback>();
  const std::string name = svc.options().name;
  RoundTrips rtt;
  Eigen::Vector3d applied = Eigen::Vector3d::Zero();
  std::uint64_t seq = 0;
  const int status = svc.run([&](const Tick& tick) {
    const device::Frame f = omni.begin_frame();
    const double now = tick.sim_time_ns * 1e-9;
    in.take([&](const ForceFeedback& s) {
      if (s.device().to_string() != name) return;
      sum.set(s.source().to_string(), device::from_idl(s.force()), now);
      rtt.answered(s.answers_seq(), mono_ns());
    });
    const Eigen::Vector3d env = sum.total(now);
    applied = omni.end_frame(passivity ? pc.filter(env, f.velocity, applied) : env);
    HapticState hs = device::haptic_state(name, seq, svc.stamp(tick), f, applied);
    rtt.sent(seq++, mono_ns());
    out.write(hs);
  });
  const Window& w = rtt.window();
  std::printf("%s: %llu ticks, %zu answered, round trip p50 %.0f us p99 %.0f us, %llu saturated, %llu sources timed out, "
              "%.3g J dissipated by the passivity controller\n",
              name.c_str(), static_cast<unsigned long long>(omni.frames()), w.size(), w.percentile(0.5),
              w.percentile(0.99), static_cast<unsigned long long>(omni.saturated()),
              static_cast<unsigned long long>(sum.expired()), pc.dissipated());
  return status;
}

}  // namespace

int main(int argc, char** argv) { return guarded_main("hcosim_haptic", [&] { return run(argc, argv); }); }
