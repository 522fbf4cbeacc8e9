// hcosim_tracker: the marker tracking service. Every step it takes the
// next frame of its camera (synthetic, an image folder, a video file, or a
// live V4L2 camera), detects the AprilTags in it, and publishes one
// MarkerPose per tag and the CameraFrame for AR compositing. With the
// synthetic camera it also measures its errors against the true pose.
// adapters::Config: docs/tracking.md.
#include <cmath>
#include <cstdio>
#include <memory>

#include "adapters/vision/calibration.h"
#include "adapters/vision/camera_config.h"
#include "adapters/vision/source.h"
#include "adapters/vision/vision_idl.h"
#include "models/vision/tracker.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

// Frames of another size are named one by one up to this many, then counted.
constexpr int kNamedSkips = 5;

int run(const Options& options) {
  Service svc(options);
  const std::string& name = svc.options().name;
  adapters::vision::CameraConfig camera = adapters::vision::camera_config(svc.params(), svc.options().rate_hz);
  const models::vision::TrackerParams& tp = camera.tracker;
  const bool publish_frames = camera.publish_frames, loop = camera.loop;
  const std::string& camera_file = camera.intrinsics_file;
  models::vision::Intrinsics& k = camera.intrinsics;
  const std::unique_ptr<adapters::vision::Source>& source = camera.source;
  const adapters::vision::SyntheticSource* synthetic = camera.synthetic;
  const std::vector<Eigen::Vector3d>& scene = camera.scene;
  std::printf("%s: %s; %s tags of %.4g m\n", name.c_str(), source->describe().c_str(), tp.detector.family.c_str(),
              tp.tag_size);
  std::fflush(stdout);

  Writer<MarkerPose> poses(svc.participant());
  Writer<CameraFrame> frames(svc.participant());
  std::unique_ptr<models::vision::Tracker> tracker;
  Window read_ms(1 << 16), track_ms(1 << 16), trans_pct(1 << 16), rot_deg(1 << 16), reg_px(1 << 16);
  std::uint64_t n_frames = 0, with_tag = 0, detections = 0, refused = 0, unreadable = 0, skipped = 0;
  bool ended = false;
  const int status = svc.run([&](const Tick& tick) {
    if (ended) return;
    adapters::vision::Frame f;
    const std::int64_t r0 = mono_ns();
    const bool got = source->next(f) || (loop && source->rewind() && source->next(f));
    read_ms.add((mono_ns() - r0) * 1e-6);
    if (!got) {
      std::printf("%s: the source ended after %llu frames\n", name.c_str(), (unsigned long long)n_frames);
      std::fflush(stdout);
      ended = true;
      svc.finish();
      return;
    }
    ++n_frames;
    if (!f.problem.empty()) {
      std::fprintf(stderr, "%s: frame %llu: %s, skipped\n", name.c_str(), (unsigned long long)f.index,
                   f.problem.c_str());
      ++unreadable;
      return;
    }
    if (!tracker) {
      k = adapters::vision::with_frame_size(k, f.image.cols, f.image.rows, camera_file);
      tracker = std::make_unique<models::vision::Tracker>(tp, k);
    }
    if (f.image.cols != k.width || f.image.rows != k.height) {
      if (++skipped <= kNamedSkips)
        std::fprintf(stderr, "%s: frame %llu is %dx%d, not the calibrated %dx%d, skipped\n", name.c_str(),
                     (unsigned long long)f.index, f.image.cols, f.image.rows, k.width, k.height);
      return;
    }
    const std::int64_t t0 = mono_ns();
    const std::vector<models::vision::Observation> seen = tracker->track(f.image);
    track_ms.add((mono_ns() - t0) * 1e-6);
    with_tag += !seen.empty();
    const StepStamp stamp = svc.stamp(tick);
    for (const models::vision::Observation& o : seen) {
      ++detections;
      MarkerPose m = adapters::vision::marker_pose(name, tp.detector.family, stamp, f.index, tp.tag_size, o,
                                                   (mono_ns() - f.capture_ns) * 1e-6);
      // A pose the subscribers would refuse (a degenerate fit) is not sent.
      if (adapters::validate(m)) {
        ++refused;
        continue;
      }
      if (synthetic && o.detection.id == synthetic->camera().marker().id) {
        const Eigen::Isometry3d truth = synthetic->truth(f.index);
        trans_pct.add(100 * (o.pose.tag_in_camera.translation() - truth.translation()).norm() /
                      truth.translation().norm());
        rot_deg.add(models::vision::angle_between(o.pose.tag_in_camera.linear(), truth.linear()) * 180 / M_PI);
        reg_px.add(models::vision::registration_error_px(k, o.pose.tag_in_camera, truth, scene));
      }
      if (poses.matched() == 0)
        svc.skip_output();
      else
        poses.write(m);
    }
    if (!publish_frames) return;
    if (frames.matched() == 0) {
      svc.skip_output();
    } else if (frames.paced() && !frames.caught_up()) {
      svc.shed_output();  // the link (network bulk_mbit) still carries the last frame
    } else {
      CameraFrame c = adapters::vision::camera_frame(name, stamp, f.index, f.image, k);
      frames.write(c);
    }
  });
  std::printf(
      "%s: %llu frames, %llu with a tag, %llu detections; reading a frame p50 %.2f ms, detection and pose "
      "p50 %.2f ms p99 %.2f ms; %llu unreadable, %llu of another size, %llu poses refused\n",
      name.c_str(), (unsigned long long)n_frames, (unsigned long long)with_tag, (unsigned long long)detections,
      read_ms.percentile(0.5), track_ms.percentile(0.5), track_ms.percentile(0.99), (unsigned long long)unreadable,
      (unsigned long long)skipped, (unsigned long long)(refused + (tracker ? tracker->unposed() : 0)));
  if (synthetic && trans_pct.size())
    std::printf(
        "%s: against the synthetic truth: translation error p50 %.3f%% p95 %.3f%% of distance, rotation "
        "error p50 %.3f deg p95 %.3f deg\n",
        name.c_str(), trans_pct.percentile(0.5), trans_pct.percentile(0.95), rot_deg.percentile(0.5),
        rot_deg.percentile(0.95));
  if (synthetic && reg_px.size())
    std::printf(
        "%s: registration error (the sheet's corners and half its edge above them) p50 %.2f px p95 %.2f px "
        "max %.2f px\n",
        name.c_str(), reg_px.percentile(0.5), reg_px.percentile(0.95), reg_px.percentile(1));
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_tracker", "the marker tracking service: AprilTag poses and camera frames", argc, argv,
                      run);
}
