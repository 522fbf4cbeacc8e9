// hcosim_rigid: the rigid body service (seed 000 §2.1; services/rigid/body_server.h).
// In real time a haptic thread answers each HapticState of its device as it
// arrives; every physics tick the loop steps the bodies and publishes each
// body's RigidBodyState, and in crosscheck mode its RigidDivergence. In
// lockstep the step answers the device's state of the same step, then
// steps the bodies. adapters::Config: docs/rigid.md.
#include <cstdio>
#include <memory>

#include "adapters/rigid/rigid_config.h"
#include "services/rigid/body_server.h"
#include "services/runtime/haptic_answer.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

int run(const Options& options) {
  Service svc(options);
  const adapters::rigid::RigidConfig config =
      adapters::rigid::rigid_config(svc.params(), svc.deployment().scene.marker);
  const double dt = 1 / svc.options().rate_hz;
  const bool realtime = svc.options().mode == adapters::Mode::kRealtime;
  if (config.backend != "analytic") {
    std::printf("%s: building the MuJoCo scene, %d substeps of %.3g ms per tick\n", svc.options().name.c_str(),
                config.mujoco_substeps, 1e3 * dt / config.mujoco_substeps);
    std::fflush(stdout);
  }
  services::rigid::BodyServer server(config, dt, realtime);

  Reader<HapticState> in = svc.reader<HapticState>();
  Writer<ForceFeedback> force(svc.participant());
  Writer<RigidBodyState> states(svc.participant());
  Writer<RigidDivergence> divergences(svc.participant());
  const auto write = [&](ForceFeedback& f) { force.write(f); };
  const bool group = in_haptic_group(svc, config.device);
  std::unique_ptr<AnswerOnArrival> haptic;
  if (realtime) {
    haptic = std::make_unique<AnswerOnArrival>(in, config.device,
                                               [&](const HapticState& s) { server.answer(s, answer_stamp(s), write); });
    lower_below(svc.options().scheduling);  // the loop steps the bodies after the haptic answers
  }
  const int status = svc.run([&](const Tick& tick) {
    const double now = tick.sim_time_ns * 1e-9;
    if (!realtime) {
      take_device_states(svc, in, force, tick, config.device, group,
                         [&](const HapticState& s) { server.keep(s, now); });
      server.answer_kept(now, svc.stamp(tick), write);
    }
    services::rigid::BodyServer::Outputs& out = server.step(now, svc.stamp(tick));
    for (RigidBodyState& s : out.states) states.matched() == 0 ? svc.skip_output() : void(states.write(s));
    for (RigidDivergence& d : out.divergences)
      divergences.matched() == 0 ? svc.skip_output() : void(divergences.write(d));
  });
  if (haptic) haptic->stop();
  server.report(stdout, svc.options().name);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_rigid", "the rigid body service: cubes and spheres touched through a god-object proxy",
                      argc, argv, run);
}
