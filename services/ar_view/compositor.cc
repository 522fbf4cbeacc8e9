#include "services/ar_view/compositor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "adapters/render/ar_idl.h"
#include "adapters/vision/vision_idl.h"
#include "services/report/plot.h"
#include "services/runtime/service.h"

namespace fs = std::filesystem;

namespace hcosim::services::ar_view {

namespace {

std::string seconds(double t) { return cv::format("%05.1fs", t); }

void write_plots(const fs::path& dir, const std::map<std::string, Trace>& traces) {
  fs::create_directories(dir);
  report::Panel all_force{"force on the stylus (N)", {}}, all_depth{"penetration (mm)", {}};
  for (const auto& [name, tr] : traces) {
    adapters::vision::write_image(
        (dir / (name + ".png")).string(),
        report::plot_series(name + ": force and penetration against simulated time", "simulated time (s)",
                            {{"force on the stylus (N)", {{name, tr.t, tr.force}}},
                             {"penetration (mm)", {{name, tr.t, tr.depth_mm}}}}));
    all_force.series.push_back({name, tr.t, tr.force});
    all_depth.series.push_back({name, tr.t, tr.depth_mm});
  }
  if (!traces.empty())
    adapters::vision::write_image((dir / "all.png").string(),
                                  report::plot_series("every object: force and penetration against simulated time",
                                                      "simulated time (s)", {all_force, all_depth}));
}

}  // namespace

void Trace::add(double time, double f, double depth) {
  if (seen++ % stride != 0) return;
  t.push_back(time), force.push_back(f), depth_mm.push_back(depth);
  if (t.size() < kPoints) return;
  for (std::size_t i = 0; 2 * i + 1 < t.size(); ++i) {
    t[i] = t[2 * i];
    force[i] = std::max(force[2 * i], force[2 * i + 1]);
    depth_mm[i] = std::max(depth_mm[2 * i], depth_mm[2 * i + 1]);
  }
  t.resize(t.size() / 2), force.resize(t.size()), depth_mm.resize(t.size());
  stride *= 2;
}

Compositor::Compositor(const adapters::render::ViewConfig& config, fs::path out, std::string name)
    : config_(config), out_(std::move(out)), name_(std::move(name)) {
  view_.force_scale = config.force_scale;
  fs::create_directories(out_);
  if (!config.video.empty()) video_path_ = out_ / config.video;
}

void Compositor::on(const MeshTopology& t) { topology_[t.mesh().to_string()] = t; }
void Compositor::on(const DeformedMesh& m) { mesh_[m.mesh().to_string()] = m; }
void Compositor::on(const RigidBodyState& b) { body_[b.body().to_string()] = b; }

void Compositor::on(const HapticState& s) {
  if (s.device().to_string() == config_.device) stylus_ = s;
}

void Compositor::on(const MarkerPose& p) {
  if (p.tag_id() == config_.tag_id && (config_.camera.empty() || p.camera().to_string() == config_.camera)) pose_ = p;
}

void Compositor::on(const ForceFeedback& f) {
  if (f.device().to_string() != config_.device) return;
  traces_[f.source().to_string()].add(f.stamp().sim_time_ns() * 1e-9,
                                      std::hypot(f.force().x(), f.force().y(), f.force().z()), 1e3 * f.penetration_m());
}

void Compositor::compose(const CameraFrame& f) {
  composite_ = adapters::vision::bgr_image(f);
  if (!pose_) return ++unregistered_, void();
  if (pose_->frame() != f.frame()) ++stale_pose_;
  view_.objects.clear();
  for (const adapters::render::ViewItem& it : config_.items) {
    if (it.kind == "rigid") {
      if (auto b = body_.find(it.name); b != body_.end())
        view_.objects.push_back({it.name, adapters::render::body(b->second, it.size), it.colour});
      continue;
    }
    const auto m = mesh_.find(it.name);
    const auto t = topology_.find(it.name);
    if (m == mesh_.end() || t == topology_.end()) continue;
    try {
      view_.objects.push_back({it.name, adapters::render::mesh(m->second, t->second), it.colour});
    } catch (const std::invalid_argument& e) {
      // A mesh of a topology not yet received: drawn from the next frame on.
      if (++bad_ <= 3) std::fprintf(stderr, "%s: %s\n", name_.c_str(), e.what());
    }
  }
  view_.stylus.reset();
  if (stylus_ && config_.stylus) view_.stylus = adapters::render::stylus(*stylus_);
  models::render::Canvas canvas(composite_, adapters::vision::intrinsics(f),
                                adapters::vision::from_idl(pose_->tag_in_camera()));
  models::render::draw(view_, canvas);
  cover_pct_.add(100.0 * double(canvas.pixels()) / double(composite_.total()));
}

void Compositor::on(const CameraFrame& f) {
  if (!config_.camera.empty() && f.camera().to_string() != config_.camera) return;
  // Frame numbers that go back are a looping source starting again: no gap.
  const std::uint64_t gap = last_frame_ && f.frame() > *last_frame_ ? f.frame() - *last_frame_ - 1 : 0;
  last_frame_ = f.frame();
  skipped_ += gap;
  const std::int64_t t0 = runtime::mono_ns();
  compose(f);
  const double t = f.stamp().sim_time_ns() * 1e-9;
  cv::putText(composite_, cv::format("t = %.2f s", t), {12, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.7,
              cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
  ++rendered_;
  if (!video_path_.empty()) {
    if (!video_) video_.emplace(video_path_.string(), "mp4v", config_.fps, composite_.size());
    for (std::uint64_t k = 0; k <= gap; ++k) video_->write(composite_), ++written_;
  }
  const std::vector<double>& snapshots = config_.snapshots;
  for (; next_snapshot_ < snapshots.size() && t + 1e-9 >= snapshots[next_snapshot_]; ++next_snapshot_) {
    const fs::path png = out_ / "snapshots" / ("ar_" + seconds(snapshots[next_snapshot_]) + ".png");
    fs::create_directories(png.parent_path());
    adapters::vision::write_image(png.string(), composite_);
    pictures_.push_back(png.string());
  }
  render_ms_.add((runtime::mono_ns() - t0) * 1e-6);
}

void Compositor::finish(std::FILE* log) {
  video_.reset();  // closes the file before it is named below
  std::fprintf(
      log,
      "%s: %llu frames drawn, %llu skipped (late, or never sent), %llu drawn with the previous frame's marker pose, "
      "%llu "
      "without any (no overlay); drawing p50 %.2f ms p99 %.2f ms; the objects cover p50 %.1f%% of a frame\n",
      name_.c_str(), (unsigned long long)rendered_, (unsigned long long)skipped_, (unsigned long long)stale_pose_,
      (unsigned long long)unregistered_, render_ms_.percentile(0.5), render_ms_.percentile(0.99),
      cover_pct_.size() ? cover_pct_.percentile(0.5) : 0.0);
  if (written_)
    std::fprintf(log, "%s: video %s, %llu frames\n", name_.c_str(), video_path_.c_str(), (unsigned long long)written_);
  for (const std::string& pic : pictures_) std::fprintf(log, "%s: picture %s\n", name_.c_str(), pic.c_str());
  const std::vector<double>& snapshots = config_.snapshots;
  if (next_snapshot_ < snapshots.size())
    std::fprintf(log, "%s: %zu picture(s) not taken: the run ended before %.3g s\n", name_.c_str(),
                 snapshots.size() - next_snapshot_, snapshots[next_snapshot_]);
  if (config_.plots) {
    // Every source that answered the device, named in the scene or not.
    write_plots(out_ / "plots", traces_);
    std::fprintf(log, "%s: plots of force and penetration in %s (%zu objects)\n", name_.c_str(),
                 (out_ / "plots").c_str(), traces_.size());
  }
}

}  // namespace hcosim::services::ar_view
