// hcosim_clock: the lockstep master. Publishes ClockTick for each base step
// and waits for every follower's StepDone before the next, so all services
// advance together whatever their speed. Protocol: docs/cosimulation.md;
// whom it waits for and how long: services/clock/roster.h.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>
#include <thread>

#include "services/clock/roster.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

int run_clock(Options options) {
  std::set<std::string> followers;
  if (!options.deployment.empty())
    for (const auto& s : adapters::load_deployment(options.deployment).services)
      if (s.unneeded.empty() && !adapters::observes(s)) followers.insert(s.name);
  options.mode = adapters::Mode::kLockstep;
  Service svc(options);
  Writer<ClockTick> ticks(svc.participant());
  Reader<StepDone> done = svc.reader<StepDone>();
  services::clock::Roster roster(followers, mono_ns());
  const int n = int(followers.size());

  // Start only when every follower can hear tick 0 and answer it: the
  // tick writer has matched a reader in each follower's own participant,
  // known from its status (a count would take a recorder's reader of
  // ClockTick for a follower's, and tick 0 would never reach that one).
  Reader<ServiceStatus> status = svc.reader<ServiceStatus>();
  std::map<std::string, eprosima::fastrtps::rtps::InstanceHandle_t> endpoint_of;  // a follower's status writer
  const auto unheard = [&] {  // followers the tick writer does not reach yet
    std::set<std::string> out;
    for (const auto& f : followers)
      if (!endpoint_of.count(f) || !ticks.reaches(endpoint_of.at(f))) out.insert(f);
    return out;
  };
  while (!unheard().empty() || done.matched() < n) {
    if (stop_requested()) return 0;
    status.take([&](const ServiceStatus& s) {
      const std::string name = s.service().to_string();
      if (followers.count(name)) endpoint_of[name] = status.current_writer();
      roster.status(name, s.state().to_string() == "starting");
    });
    if (const std::string why = roster.join_failure(mono_ns(), done.matched(), unheard()); !why.empty()) {
      std::cerr << "clock: " << why << "\n";
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }

  const std::int64_t step_ns = std::llround(options.step_s * 1e9);
  const std::uint64_t last =
      options.duration_s > 0 ? std::uint64_t(std::llround(options.duration_s / options.step_s)) - 1 : UINT64_MAX;
  const std::int64_t wall_start = mono_ns();
  std::uint64_t k = 0;
  for (;; ++k) {
    const bool is_last = k == last || stop_requested();
    const std::int64_t t0 = mono_ns();
    ClockTick tick;
    tick.step(k);
    tick.sim_time_ns(std::int64_t(k) * step_ns);
    tick.step_ns(step_ns);
    tick.last(is_last);
    ticks.write(tick);
    roster.tick(k, mono_ns());
    while (!roster.complete()) {
      if (stop_requested()) {
        std::printf("clock: stopped at step %llu\n", static_cast<unsigned long long>(k));
        svc.settle();
        return 0;
      }
      if (const std::string why = roster.step_failure(mono_ns()); !why.empty()) {
        std::cerr << "clock: " << why << "\n";
        return 1;
      }
      if (done.wait(std::chrono::milliseconds(100)))
        done.take([&](const StepDone& d) { roster.done(d.step(), d.service().to_string()); });
    }
    svc.record_step(0.0, (mono_ns() - t0) * 1e-3, false);
    svc.heartbeat(tick.sim_time_ns(), k);
    if (is_last) break;
  }
  const double wall_s = (mono_ns() - wall_start) * 1e-9;
  const double sim_s = double(k + 1) * options.step_s;
  std::printf("clock: %llu steps, %.3f s simulated in %.3f s wall (real-time factor %.2f), %d followers\n",
              static_cast<unsigned long long>(k + 1), sim_s, wall_s, sim_s / wall_s, n);
  svc.settle();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_clock", "the lockstep master: one ClockTick a base step, after every follower's StepDone",
                      argc, argv, run_clock);
}
