// hcosim_haptic: the haptic device service (services/haptic/servo_loop.h).
// Each servo tick it publishes the device's HapticState, then waits (up to
// `answer_wait`) for every source it expects to answer that state, and
// renders the sum of their forces. In lockstep the device and the sources
// at its rate form one Gauss-Seidel group: the force of step k answers the
// state of step k. adapters::Config: docs/haptic.md.
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "adapters/device/device_config.h"
#include "services/haptic/servo_loop.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

// Lockstep: how long a step waits for its group's answers before failing.
constexpr double kGroupWaitS = 10;

int run(const Options& options) {
  Service svc(options);
  const adapters::device::DeviceConfig config = adapters::device::device_config(svc.params(), svc.options().rate_hz);
  const std::string name = svc.options().name;
  const bool lockstep = svc.options().mode == adapters::Mode::kLockstep;
  // In real time a source is waited for once it has answered and while it
  // stays fresh (a service still building its model is not yet a source;
  // one that died drops out after source_timeout). In lockstep the sources
  // the deployment names at this rate are the Gauss-Seidel group, waited
  // for from the first step.
  std::vector<std::string> group;
  for (const adapters::ForceSource& fs : adapters::force_sources(svc.deployment(), name))
    if (fs.rate_hz == svc.options().rate_hz) group.push_back(fs.object);
  services::haptic::ServoLoop loop(config, name, group, lockstep, stdout);

  Writer<HapticState> out(svc.participant());
  Reader<ForceFeedback> in = svc.reader<ForceFeedback>();
  const int status = svc.run([&](const Tick& tick) {
    HapticState hs = loop.begin(tick, svc.stamp(tick));
    out.write(hs);
    const auto take = [&](const ForceFeedback& s) { loop.take(s, tick.step); };
    if (loop.gauss_seidel()) {
      const std::int64_t deadline = loop.sent_ns() + std::int64_t(kGroupWaitS * 1e9);
      for (;;) {
        in.take_before(tick.step + 1, take);
        if (!loop.waiting() || stop_requested()) break;
        if (mono_ns() > deadline)
          throw std::runtime_error(name + ": step " + std::to_string(tick.step) +
                                   ": the sources of its group did not answer in " + std::to_string(int(kGroupWaitS)) +
                                   " s");
        in.wait(std::chrono::milliseconds(100));
      }
    } else {
      svc.take(in, tick, take);
      loop.expect();
      // In lockstep outside a group, this tick's answers belong to the next
      // tick: no wait.
      const std::int64_t deadline = loop.sent_ns() + std::int64_t(lockstep ? 0 : config.answer_wait * 1e9);
      while (loop.waiting() && mono_ns() < deadline && in.wait(std::chrono::nanoseconds(deadline - mono_ns())))
        svc.take(in, tick, take);
    }
    loop.end();
    if (loop.ticks() % 1000 == 0) svc.set_haptic_figures(loop.in_tick_ratio(), loop.force_error_p99());
  });
  svc.set_haptic_figures(loop.in_tick_ratio(), loop.force_error_p99());
  if (!config.report.empty()) {
    std::ofstream r(config.report);
    r << loop.report_json() << "\n";
    if (!r) throw std::runtime_error("cannot write " + config.report);
  }
  loop.report(stdout);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_haptic",
                      "the haptic device service: reads the device, renders the sum of its sources' forces", argc, argv,
                      run);
}
