// What the AR view makes, without DDS: each camera frame with every object
// of the scene (deformed meshes, rigid bodies), the stylus and the force it
// renders drawn over it, registered by the marker's pose; the video of
// those frames, PNG pictures at chosen moments, and at the end plots of
// each object's force and penetration against time.
// services/ar_view/main.cc wires it to its topics.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "adapters/render/view_config.h"
#include "adapters/vision/media.h"
#include "idl/haptic.h"
#include "idl/mesh.h"
#include "idl/rigid.h"
#include "idl/vision.h"
#include "models/render/view.h"
#include "services/runtime/stats.h"

namespace hcosim::services::ar_view {

// One object's force and penetration over time, for the plots at the end,
// in at most kPoints points: when full, each pair of points becomes one
// (the larger force and depth: peaks stay) and new samples are taken one in
// twice as many, so a run of hours keeps the whole run's shape in bounded
// memory. A 20 s run at 1 kHz keeps every sample.
struct Trace {
  static constexpr std::size_t kPoints = 1 << 15;
  std::vector<double> t, force, depth_mm;
  std::uint64_t stride = 1, seen = 0;
  void add(double time, double f, double depth);
};

class Compositor {
 public:
  // Writes into the folder `out`; `name` (the service's) starts its lines.
  Compositor(const adapters::render::ViewConfig& config, std::filesystem::path out, std::string name);
  Compositor(const Compositor&) = delete;
  Compositor& operator=(const Compositor&) = delete;

  // What the next frame draws: the latest of each. Samples of another
  // device, marker or camera than the config's are ignored.
  void on(const MeshTopology& t);
  void on(const DeformedMesh& m);
  void on(const RigidBodyState& b);
  void on(const HapticState& s);
  void on(const MarkerPose& p);
  // An answer to the device: a point of its source's force and
  // penetration trace.
  void on(const ForceFeedback& f);
  // Draws over the frame and writes it to the video (again for each frame
  // the camera numbered but never sent, so that the video keeps the
  // camera's time) and to the pictures whose moment it reaches.
  void on(const CameraFrame& f);

  // Closes the video, writes the plots, and the closing lines to `log`.
  void finish(std::FILE* log);

  const cv::Mat& composite() const { return composite_; }  // the last frame drawn
  std::uint64_t rendered() const { return rendered_; }
  const std::map<std::string, Trace>& traces() const { return traces_; }

 private:
  void compose(const CameraFrame& f);

  adapters::render::ViewConfig config_;
  std::filesystem::path out_, video_path_;
  std::string name_;
  models::render::View view_;
  std::map<std::string, MeshTopology> topology_;
  std::map<std::string, DeformedMesh> mesh_;
  std::map<std::string, RigidBodyState> body_;
  std::map<std::string, Trace> traces_;
  std::optional<HapticState> stylus_;
  std::optional<MarkerPose> pose_;
  std::optional<std::uint64_t> last_frame_;
  std::optional<adapters::vision::VideoOut> video_;
  cv::Mat composite_;
  std::size_t next_snapshot_ = 0;
  runtime::Window render_ms_{1 << 16}, cover_pct_{1 << 16};
  std::uint64_t rendered_ = 0, skipped_ = 0, stale_pose_ = 0, unregistered_ = 0, bad_ = 0, written_ = 0;
  std::vector<std::string> pictures_;
};

}  // namespace hcosim::services::ar_view
