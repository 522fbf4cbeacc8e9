// hcosim_tracker: the marker tracking service. Every step it takes the
// next frame of its camera (synthetic, an image folder, a video file, or a
// live V4L2 camera), detects the AprilTags in it, and publishes one
// MarkerPose per tag and the CameraFrame for AR compositing. With the
// synthetic camera it also measures its errors against the true pose.
// Params: docs/tracking.md.
#include <cmath>
#include <cstdio>
#include <memory>

#include "adapters/vision/calibration.h"
#include "adapters/vision/source.h"
#include "adapters/vision/vision_idl.h"
#include "models/vision/tracker.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

// Frames of another size are named one by one up to this many, then counted.
constexpr int kNamedSkips = 5;

models::vision::TrackerParams tracker_params(const Params& p) {
  models::vision::TrackerParams t;
  models::vision::DetectorParams& d = t.detector;
  d.family = p.text("family", d.family, {"tag36h11", "tag25h9", "tag16h5", "tagStandard41h12"});
  d.quad_decimate = p.number("quad_decimate", d.quad_decimate, 1, 8);
  d.quad_sigma = p.number("quad_sigma", d.quad_sigma, -5, 5);
  d.nthreads = p.whole("nthreads", d.nthreads, 1, 64);
  d.refine_edges = p.on("refine_edges", d.refine_edges);
  d.decode_sharpening = p.number("decode_sharpening", d.decode_sharpening, 0, 10);
  d.max_hamming = p.whole("max_hamming", d.max_hamming, 0, 3);
  d.refine_corners = p.on("refine_corners", d.refine_corners);
  t.pose.refine = p.on("refine_pose", t.pose.refine);
  t.tag_size = p.number("tag_size", t.tag_size, 1e-3, 10);
  return t;
}

models::vision::Orbit orbit_params(const Params& p) {
  p.allow_only({"distance", "swing", "tilt", "base_tilt", "period", "upright", "sweep"});
  models::vision::Orbit o;
  o.distance = p.number("distance", o.distance, 0.05, 100);
  o.swing = p.number("swing", o.swing, 0, 0.9 * o.distance);
  o.tilt_deg = p.number("tilt", o.tilt_deg, 0, 79);
  o.base_tilt_deg = p.number("base_tilt", o.base_tilt_deg, 0, 79 - o.tilt_deg);
  o.period = p.number("period", o.period, 0.1, 1e6);
  o.upright = p.on("upright", false);
  o.sweep_deg = p.number("sweep", o.sweep_deg, 0, 179);
  return o;
}

int run(int argc, char** argv) {
  Service svc(parse_options(argc, argv));
  const Params& p = svc.params();
  const std::string& name = svc.options().name;
  p.allow_only({"source",        "path",           "device",      "camera",       "width",
                "height",        "condition",      "tag_id",      "family",       "tag_size",
                "quad_decimate", "quad_sigma",     "nthreads",    "refine_edges", "decode_sharpening",
                "max_hamming",   "refine_corners", "refine_pose", "frames",       "loop",
                "sheet",         "orbit"});
  const std::string kind = p.text("source", "synthetic", {"synthetic", "folder", "video", "v4l2"});
  const models::vision::TrackerParams tp = tracker_params(p);
  const bool publish_frames = p.on("frames", true), loop = p.on("loop", false);
  const int width = p.whole("width", 640, 16, 8192), height = p.whole("height", 480, 16, 8192);
  const std::string camera_file = p.path("camera");

  // The source, and the intrinsics its frames were taken with.
  std::unique_ptr<adapters::vision::Source> source;
  adapters::vision::SyntheticSource* synthetic = nullptr;
  std::vector<Eigen::Vector3d> scene;  // synthetic: where registration is measured, tag frame, m
  models::vision::Intrinsics k;
  if (kind != "synthetic" && camera_file.empty())
    p.fail("camera", "source '" + kind + "' needs camera: an intrinsics file in OpenCV's calibration format");
  if (!camera_file.empty()) k = adapters::vision::read_intrinsics(camera_file);
  if (kind == "synthetic") {
    models::vision::Marker m;
    m.family = tp.detector.family;
    m.id = p.whole("tag_id", 0, 0, 1000000);
    m.tag_size = tp.tag_size;
    m.sheet = p.number("sheet", m.sheet, 1.25, 10);
    const models::vision::Orbit path = orbit_params(p.map("orbit"));
    if (camera_file.empty()) k = models::vision::synthetic_intrinsics(width, height);
    k = adapters::vision::with_frame_size(k, width, height, camera_file);
    auto s = std::make_unique<adapters::vision::SyntheticSource>(
        models::vision::SyntheticCamera(k, m),
        models::vision::condition(p.text("condition", "clean", {"clean", "noisy", "blurred"})), svc.options().rate_hz,
        0, path);
    // The sheet's corners on the table and half its edge above it: where
    // the scene's objects stand.
    const double h = 0.5 * m.sheet * m.tag_size;
    for (double z : {0.0, h})
      for (double x : {-h, h})
        for (double y : {-h, h}) scene.emplace_back(x, y, z);
    synthetic = s.get();
    source = std::move(s);
  } else if (kind == "v4l2") {
    source = adapters::vision::open_v4l2(p.string("device", "/dev/video0"), width, height, svc.options().rate_hz);
  } else {
    const std::string path = p.path("path");
    if (path.empty())
      p.fail("path", "source '" + kind + "' needs path: the " + (kind == "video" ? "video file" : "image folder"));
    source = kind == "video" ? adapters::vision::open_video(path) : adapters::vision::open_folder(path);
  }
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
  return guarded_main("hcosim_tracker", [&] { return run(argc, argv); });
}
