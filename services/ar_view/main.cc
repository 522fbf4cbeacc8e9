// hcosim_ar_view: the AR view. At the camera's rate it draws every object
// of the scene (deformed meshes, rigid bodies), the stylus and the force
// it renders over each camera frame, registered by the marker's pose, and
// writes the video; PNG pictures at chosen moments; and at the end, plots
// of each object's force and penetration against time. Headless.
// adapters::Config: docs/arview.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "adapters/render/ar_idl.h"
#include "adapters/render/view_config.h"
#include "adapters/vision/media.h"
#include "adapters/vision/vision_idl.h"
#include "services/report/plot.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;
namespace fs = std::filesystem;

namespace {

// ForceFeedback samples kept per source between two frames: a 1 kHz
// source gives 33 to 40 at a camera's rate; more room absorbs a late step.
constexpr int kTraceDepth = 256;

// One object's force and penetration over time, for the plots at the end,
// in at most kTracePoints points: when full, each pair of points becomes
// one (the larger force and depth: peaks stay) and new samples are taken
// one in twice as many, so a run of hours keeps the whole run's shape in
// bounded memory (it grew 4 MB a minute: bench soak). A 20 s run at 1 kHz
// keeps every sample.
constexpr std::size_t kTracePoints = 1 << 15;
struct Trace {
  std::vector<double> t, force, depth_mm;
  std::uint64_t stride = 1, seen = 0;
  void add(double time, double f, double depth) {
    if (seen++ % stride != 0) return;
    t.push_back(time), force.push_back(f), depth_mm.push_back(depth);
    if (t.size() < kTracePoints) return;
    for (std::size_t i = 0; 2 * i + 1 < t.size(); ++i) {
      t[i] = t[2 * i];
      force[i] = std::max(force[2 * i], force[2 * i + 1]);
      depth_mm[i] = std::max(depth_mm[2 * i], depth_mm[2 * i + 1]);
    }
    t.resize(t.size() / 2), force.resize(t.size()), depth_mm.resize(t.size());
    stride *= 2;
  }
};

std::string seconds(double t) { return cv::format("%05.1fs", t); }

void write_plots(const fs::path& dir, const std::map<std::string, Trace>& traces) {
  fs::create_directories(dir);
  services::report::Panel all_force{"force on the stylus (N)", {}}, all_depth{"penetration (mm)", {}};
  for (const auto& [name, tr] : traces) {
    adapters::vision::write_image(
        (dir / (name + ".png")).string(),
        services::report::plot_series(name + ": force and penetration against simulated time", "simulated time (s)",
                                      {{"force on the stylus (N)", {{name, tr.t, tr.force}}},
                                       {"penetration (mm)", {{name, tr.t, tr.depth_mm}}}}));
    all_force.series.push_back({name, tr.t, tr.force});
    all_depth.series.push_back({name, tr.t, tr.depth_mm});
  }
  if (!traces.empty())
    adapters::vision::write_image(
        (dir / "all.png").string(),
        services::report::plot_series("every object: force and penetration against simulated time",
                                      "simulated time (s)", {all_force, all_depth}));
}

int run(const Options& options) {
  Service svc(options);
  const adapters::render::ViewConfig config = adapters::render::view_config(svc.params(), svc.options().rate_hz);
  const std::string& name = svc.options().name;
  const std::string& camera = config.camera;
  const int tag_id = config.tag_id;
  const std::string& device = config.device;
  const std::vector<adapters::render::ViewItem>& items = config.items;
  const std::vector<double>& snapshots = config.snapshots;
  const bool plots = config.plots, show_stylus = config.stylus;
  models::render::View view;
  view.force_scale = config.force_scale;
  const fs::path out = svc.options().out;
  const std::string& video_name = config.video;
  const double fps = config.fps;
  fs::create_directories(out);
  const fs::path video_path = video_name.empty() ? fs::path() : out / video_name;

  Reader<CameraFrame> frames = svc.reader<CameraFrame>();
  Reader<MarkerPose> poses = svc.reader<MarkerPose>();
  Reader<DeformedMesh> meshes = svc.reader<DeformedMesh>();
  Reader<MeshTopology> topologies = svc.reader<MeshTopology>();
  Reader<RigidBodyState> bodies = svc.reader<RigidBodyState>();
  Reader<HapticState> haptic = svc.reader<HapticState>();
  Reader<ForceFeedback> forces = svc.reader<ForceFeedback>(TopicOf<ForceFeedback>::qos, kTraceDepth);

  std::map<std::string, MeshTopology> topology;
  std::map<std::string, DeformedMesh> mesh;
  std::map<std::string, RigidBodyState> body;
  std::map<std::string, Trace> traces;
  std::optional<HapticState> stylus;
  std::optional<MarkerPose> pose;
  std::optional<std::uint64_t> last_frame;
  std::optional<adapters::vision::VideoOut> video;
  cv::Mat composite;
  std::size_t next_snapshot = 0;
  Window render_ms(1 << 16), cover_pct(1 << 16);
  std::uint64_t rendered = 0, skipped = 0, stale_pose = 0, unregistered = 0, bad = 0, written = 0;
  std::vector<std::string> pictures;

  const auto compose = [&](const CameraFrame& f) {
    composite = adapters::vision::bgr_image(f);
    if (!pose) return ++unregistered, void();
    if (pose->frame() != f.frame()) ++stale_pose;
    view.objects.clear();
    for (const adapters::render::ViewItem& it : items) {
      if (it.kind == "rigid") {
        if (auto b = body.find(it.name); b != body.end())
          view.objects.push_back({it.name, adapters::render::body(b->second, it.size), it.colour});
        continue;
      }
      const auto m = mesh.find(it.name);
      const auto t = topology.find(it.name);
      if (m == mesh.end() || t == topology.end()) continue;
      try {
        view.objects.push_back({it.name, adapters::render::mesh(m->second, t->second), it.colour});
      } catch (const std::invalid_argument& e) {
        // A mesh of a topology not yet received: drawn from the next frame on.
        if (++bad <= 3) std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
      }
    }
    view.stylus.reset();
    if (stylus && show_stylus) view.stylus = adapters::render::stylus(*stylus);
    models::render::Canvas canvas(composite, adapters::vision::intrinsics(f),
                                  adapters::vision::from_idl(pose->tag_in_camera()));
    models::render::draw(view, canvas);
    cover_pct.add(100.0 * double(canvas.pixels()) / double(composite.total()));
  };

  const int status = svc.run([&](const Tick& tick) {
    topologies.take([&](const MeshTopology& t) { topology[t.mesh().to_string()] = t; });
    svc.take(meshes, tick, [&](const DeformedMesh& m) { mesh[m.mesh().to_string()] = m; });
    svc.take(bodies, tick, [&](const RigidBodyState& b) { body[b.body().to_string()] = b; });
    svc.take(haptic, tick, [&](const HapticState& s) {
      if (s.device().to_string() == device) stylus = s;
    });
    svc.take(forces, tick, [&](const ForceFeedback& f) {
      if (f.device().to_string() != device) return;
      traces[f.source().to_string()].add(f.stamp().sim_time_ns() * 1e-9,
                                         std::hypot(f.force().x(), f.force().y(), f.force().z()),
                                         1e3 * f.penetration_m());
    });
    svc.take(poses, tick, [&](const MarkerPose& m) {
      if (m.tag_id() == tag_id && (camera.empty() || m.camera().to_string() == camera)) pose = m;
    });
    svc.take(frames, tick, [&](const CameraFrame& f) {
      if (!camera.empty() && f.camera().to_string() != camera) return;
      // Frame numbers that go back are a looping source starting again: no gap.
      const std::uint64_t gap = last_frame && f.frame() > *last_frame ? f.frame() - *last_frame - 1 : 0;
      last_frame = f.frame();
      skipped += gap;
      const std::int64_t t0 = mono_ns();
      compose(f);
      const double t = f.stamp().sim_time_ns() * 1e-9;
      cv::putText(composite, cv::format("t = %.2f s", t), {12, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.7,
                  cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
      ++rendered;
      if (!video_path.empty()) {
        if (!video) video.emplace(video_path.string(), "mp4v", fps, composite.size());
        // A skipped frame repeats the one before it, so the video keeps the camera's time.
        for (std::uint64_t k = 0; k <= gap; ++k) video->write(composite), ++written;
      }
      for (; next_snapshot < snapshots.size() && t + 1e-9 >= snapshots[next_snapshot]; ++next_snapshot) {
        const fs::path png = out / "snapshots" / ("ar_" + seconds(snapshots[next_snapshot]) + ".png");
        fs::create_directories(png.parent_path());
        adapters::vision::write_image(png.string(), composite);
        pictures.push_back(png.string());
      }
      render_ms.add((mono_ns() - t0) * 1e-6);
    });
  });
  video.reset();  // closes the file before it is named below
  std::printf(
      "%s: %llu frames drawn, %llu skipped (late, or never sent), %llu drawn with the previous frame's marker pose, "
      "%llu "
      "without any (no overlay); drawing p50 %.2f ms p99 %.2f ms; the objects cover p50 %.1f%% of a frame\n",
      name.c_str(), (unsigned long long)rendered, (unsigned long long)skipped, (unsigned long long)stale_pose,
      (unsigned long long)unregistered, render_ms.percentile(0.5), render_ms.percentile(0.99),
      cover_pct.size() ? cover_pct.percentile(0.5) : 0.0);
  if (written)
    std::printf("%s: video %s, %llu frames\n", name.c_str(), video_path.c_str(), (unsigned long long)written);
  for (const std::string& pic : pictures) std::printf("%s: picture %s\n", name.c_str(), pic.c_str());
  if (next_snapshot < snapshots.size())
    std::printf("%s: %zu picture(s) not taken: the run ended before %.3g s\n", name.c_str(),
                snapshots.size() - next_snapshot, snapshots[next_snapshot]);
  if (plots) {
    // Every source that answered the device, named in the scene or not.
    write_plots(out / "plots", traces);
    std::printf("%s: plots of force and penetration in %s (%zu objects)\n", name.c_str(), (out / "plots").c_str(),
                traces.size());
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_ar_view",
                      "the AR view: draws the scene over each camera frame and writes the video, pictures and plots",
                      argc, argv, run);
}
