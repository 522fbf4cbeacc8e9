#include "adapters/vision/camera_config.h"

#include "adapters/vision/calibration.h"

namespace hcosim::adapters::vision {
namespace {

models::vision::Orbit orbit_params(const Config& p) {
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

models::vision::TrackerParams tracker_params(const Config& p, const MarkerSpec& marker) {
  models::vision::TrackerParams t;
  models::vision::DetectorParams& d = t.detector;
  d.family = p.text("family", marker.family.value_or(d.family), tag::kFamilies);
  d.quad_decimate = p.number("quad_decimate", d.quad_decimate, 1, 8);
  d.quad_sigma = p.number("quad_sigma", d.quad_sigma, -5, 5);
  d.nthreads = p.whole("nthreads", d.nthreads, 1, 64);
  d.refine_edges = p.on("refine_edges", d.refine_edges);
  d.decode_sharpening = p.number("decode_sharpening", d.decode_sharpening, 0, 10);
  d.max_hamming = p.whole("max_hamming", d.max_hamming, 0, 3);
  d.refine_corners = p.on("refine_corners", d.refine_corners);
  t.pose.refine = p.on("refine_pose", t.pose.refine);
  t.tag_size = p.number("tag_size", marker.size.value_or(t.tag_size), tag::kMinSize, tag::kMaxSize);
  return t;
}

}  // namespace

CameraConfig camera_config(const Config& p, double rate_hz, const MarkerSpec& marker) {
  p.allow_only({"source",        "path",           "device",      "camera",       "width",
                "height",        "condition",      "tag_id",      "family",       "tag_size",
                "quad_decimate", "quad_sigma",     "nthreads",    "refine_edges", "decode_sharpening",
                "max_hamming",   "refine_corners", "refine_pose", "frames",       "loop",
                "sheet",         "orbit"});
  const std::string kind = p.text("source", "synthetic", {"synthetic", "folder", "video", "v4l2"});
  CameraConfig c;
  c.tracker = tracker_params(p, marker);
  const models::vision::TrackerParams& tp = c.tracker;
  c.publish_frames = p.on("frames", c.publish_frames);
  c.loop = p.on("loop", c.loop);
  const int width = p.whole("width", 640, 16, 8192), height = p.whole("height", 480, 16, 8192);
  c.intrinsics_file = p.path("camera");
  const std::string& camera_file = c.intrinsics_file;

  // The source, and the intrinsics its frames were taken with.
  models::vision::Intrinsics& k = c.intrinsics;
  if (kind != "synthetic" && camera_file.empty())
    p.fail("camera", "source '" + kind + "' needs camera: an intrinsics file in OpenCV's calibration format");
  if (!camera_file.empty()) k = read_intrinsics(camera_file);
  if (kind == "synthetic") {
    models::vision::Marker m;
    m.family = tp.detector.family;
    m.id = p.whole("tag_id", marker.id.value_or(0), 0, tag::kMaxId);
    m.tag_size = tp.tag_size;
    m.sheet = p.number("sheet", m.sheet, 1.25, 10);
    const models::vision::Orbit path = orbit_params(p.map("orbit"));
    if (camera_file.empty()) k = models::vision::synthetic_intrinsics(width, height);
    k = with_frame_size(k, width, height, camera_file);
    auto s = std::make_unique<SyntheticSource>(
        models::vision::SyntheticCamera(k, m),
        models::vision::condition(p.text("condition", "clean", {"clean", "noisy", "blurred"})), rate_hz, 0, path);
    // The sheet's corners on the table and half its edge above it: where
    // the scene's objects stand.
    const double h = 0.5 * m.sheet * m.tag_size;
    for (double z : {0.0, h})
      for (double x : {-h, h})
        for (double y : {-h, h}) c.scene.emplace_back(x, y, z);
    c.synthetic = s.get();
    c.source = std::move(s);
  } else if (kind == "v4l2") {
    c.source = open_v4l2(p.string("device", "/dev/video0"), width, height, rate_hz);
  } else {
    const std::string path = p.path("path");
    if (path.empty())
      p.fail("path", "source '" + kind + "' needs path: the " + (kind == "video" ? "video file" : "image folder"));
    c.source = kind == "video" ? open_video(path) : open_folder(path);
  }
  return c;
}

}  // namespace hcosim::adapters::vision
