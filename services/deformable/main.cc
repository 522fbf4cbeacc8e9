// hcosim_deformable: the deformable object service (seed 001's hybrid
// model, seed 000's elastic sheet and semi-sphere;
// services/deformable/object_server.h). In real time a haptic thread
// answers each HapticState of its device as it arrives. The loop, at
// normal priority, advances the objects' behavior models at their own
// rate; at the visual rate a worker thread maps and publishes each
// object's DeformedMesh (visual_worker.h), unless no reader is matched. In
// lockstep the step answers the device's state of the same step, then
// advances. Topologies are written once, latched for late joiners.
// adapters::Config: docs/deformable.md.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "adapters/deformable/deformable_config.h"
#include "services/deformable/object_server.h"
#include "services/deformable/visual_worker.h"
#include "services/runtime/haptic_answer.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

int run(const Options& options) {
  Service svc(options);
  const double servo_dt = 1 / svc.options().rate_hz;
  const bool realtime = svc.options().mode == adapters::Mode::kRealtime;
  const adapters::deformable::DeformableConfig config = adapters::deformable::deformable_config(svc.params(), servo_dt);
  const double visual_period = 1 / config.visual_rate_hz;
  // HCOSIM_CACHE lets several runs share one folder of maps and gains
  // (the integration tests do); writes are whole files, renamed into place.
  const char* shared = std::getenv("HCOSIM_CACHE");
  const std::string cache = shared && *shared ? shared : svc.options().out + "/cache";
  services::deformable::ObjectServer objects(config, servo_dt, realtime, cache, stdout);

  Reader<HapticState> in = svc.reader<HapticState>();
  Writer<ForceFeedback> force(svc.participant());
  Writer<DeformedMesh> meshes(svc.participant());
  Writer<MeshTopology> topology(svc.participant());
  for (MeshTopology& t : objects.topologies()) topology.write(t);
  const auto write = [&](ForceFeedback& f) { force.write(f); };
  const bool group = in_haptic_group(svc, config.device);
  std::unique_ptr<AnswerOnArrival> haptic;
  if (realtime) {
    haptic = std::make_unique<AnswerOnArrival>(
        in, config.device, [&](const HapticState& s) { objects.answer(s, answer_stamp(s), write); });
    lower_below(svc.options().scheduling);  // the loop after the haptic answers; the visual worker lowers itself
  }
  services::deformable::VisualWorker visual(svc, meshes, objects);
  double next_frame = 0;
  const int status = svc.run([&](const Tick& tick) {
    const double now = tick.sim_time_ns * 1e-9;
    if (!realtime) {
      take_device_states(svc, in, force, tick, config.device, group, [&](const HapticState& s) { objects.keep(s); });
      objects.answer_kept(svc.stamp(tick), write);
    }
    objects.advance(now);
    if (now + 1e-12 < next_frame) return;
    next_frame += visual_period;
    if (meshes.matched() == 0)
      for (std::size_t k = 0; k < objects.size(); ++k) svc.skip_output();
    else
      visual.post(objects.cages(), svc.stamp(tick), !realtime);
  });
  if (haptic) haptic->stop();
  visual.stop();
  objects.report(stdout, svc.options().name, visual.stats());
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_deformable", "the deformable object service: hybrid model, elastic sheet and semi-sphere",
                      argc, argv, run);
}
