// hcosim_ar_view: the AR view (services/ar_view/compositor.h). At the
// camera's rate it draws every object of the scene, the stylus and its
// force over each camera frame, registered by the marker's pose, and writes
// the video; PNG pictures at chosen moments; and at the end, plots of each
// object's force and penetration against time. Headless.
// adapters::Config: docs/arview.md.
#include <cstdio>

#include "adapters/render/view_config.h"
#include "services/ar_view/compositor.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

// ForceFeedback samples kept per source between two frames: a 1 kHz
// source gives 33 to 40 at a camera's rate; more room absorbs a late step.
constexpr int kTraceDepth = 256;

int run(const Options& options) {
  Service svc(options);
  services::ar_view::Compositor view(
      adapters::render::view_config(svc.params(), svc.options().rate_hz, svc.deployment().scene.marker),
      svc.options().out, svc.options().name);
  Reader<CameraFrame> frames = svc.reader<CameraFrame>();
  Reader<MarkerPose> poses = svc.reader<MarkerPose>();
  Reader<DeformedMesh> meshes = svc.reader<DeformedMesh>();
  Reader<MeshTopology> topologies = svc.reader<MeshTopology>();
  Reader<RigidBodyState> bodies = svc.reader<RigidBodyState>();
  Reader<HapticState> haptic = svc.reader<HapticState>();
  Reader<ForceFeedback> forces = svc.reader<ForceFeedback>(TopicOf<ForceFeedback>::qos, kTraceDepth);
  const auto draw = [&](const auto& sample) { view.on(sample); };
  const int status = svc.run([&](const Tick& tick) {
    topologies.take(draw);
    svc.take(meshes, tick, draw);
    svc.take(bodies, tick, draw);
    svc.take(haptic, tick, draw);
    svc.take(forces, tick, draw);
    svc.take(poses, tick, draw);
    svc.take(frames, tick, draw);
  });
  view.finish(stdout);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_ar_view",
                      "the AR view: draws the scene over each camera frame and writes the video, pictures and plots",
                      argc, argv, run);
}
