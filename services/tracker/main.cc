// hcosim_tracker: the marker tracking service (services/tracker/frame_tracker.h).
// Every step it takes the next frame of its camera (synthetic, an image
// folder, a video file, or a live V4L2 camera), detects the AprilTags in
// it, and publishes one MarkerPose per tag and the CameraFrame for AR
// compositing. With the synthetic camera it also measures its errors
// against the true pose. adapters::Config: docs/tracking.md.
#include <cstdio>

#include "adapters/vision/camera_config.h"
#include "services/runtime/service.h"
#include "services/tracker/frame_tracker.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

int run(const Options& options) {
  Service svc(options);
  const std::string& name = svc.options().name;
  services::tracker::FrameTracker tracker(
      adapters::vision::camera_config(svc.params(), svc.options().rate_hz, svc.deployment().scene.marker), name,
      stdout);
  const adapters::vision::CameraConfig& camera = tracker.camera();
  std::printf("%s: %s; %s tags of %.4g m\n", name.c_str(), camera.source->describe().c_str(),
              camera.tracker.detector.family.c_str(), camera.tracker.tag_size);
  std::fflush(stdout);

  Writer<MarkerPose> poses(svc.participant());
  Writer<CameraFrame> frames(svc.participant());
  bool ended = false;
  const int status = svc.run([&](const Tick& tick) {
    if (ended) return;
    const StepStamp stamp = svc.stamp(tick);
    if (!tracker.step(stamp)) {
      ended = true;
      svc.finish();
      return;
    }
    for (const MarkerPose& m : tracker.poses()) {
      MarkerPose sample = m;
      poses.matched() == 0 ? svc.skip_output() : void(poses.write(sample));
    }
    if (!camera.publish_frames || !tracker.has_frame()) return;
    if (frames.matched() == 0) {
      svc.skip_output();
    } else if (frames.paced() && !frames.caught_up()) {
      svc.shed_output();  // the link (network bulk_mbit) still carries the last frame
    } else {
      CameraFrame c = tracker.frame(stamp);
      frames.write(c);
    }
  });
  tracker.report(stdout);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_tracker", "the marker tracking service: AprilTag poses and camera frames", argc, argv,
                      run);
}
