// What the marker tracking service does each step, without DDS: the
// camera's next frame, every AprilTag in it posed (models/vision/tracker.h)
// as the MarkerPose samples to publish, those a subscriber would refuse
// left out, and against a synthetic camera's ground truth each pose's
// error. services/tracker/main.cc wires it to its topics.
#pragma once

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "adapters/vision/camera_config.h"
#include "idl/vision.h"
#include "models/vision/tracker.h"
#include "services/runtime/stats.h"

namespace hcosim::services::tracker {

class FrameTracker {
 public:
  // `name`: the camera's (MarkerPose.camera, the service's name). Problems
  // with frames are said on `log`.
  FrameTracker(adapters::vision::CameraConfig camera, std::string name, std::FILE* log);
  FrameTracker(const FrameTracker&) = delete;
  FrameTracker& operator=(const FrameTracker&) = delete;

  // One step: reads the next frame (a looping source starts again at its
  // end) and poses its tags, stamped `stamp`. False once the source has
  // ended (said once on `log`); the poses and the frame are then empty.
  bool step(const StepStamp& stamp);
  // This step's poses, admissible ones only.
  const std::vector<MarkerPose>& poses() const { return poses_; }
  // Whether this step read a frame of the calibrated size, and it as a
  // CameraFrame for the AR view.
  bool has_frame() const { return has_frame_; }
  CameraFrame frame(const StepStamp& stamp) const;

  // Writes the closing lines to `out`: frames, detections and their cost,
  // and against a synthetic camera's truth, the pose and registration errors.
  void report(std::FILE* out) const;

  const adapters::vision::CameraConfig& camera() const { return camera_; }

  static constexpr int kNamedSkips = 5;  // frames of another size named one by one, then counted

 private:
  adapters::vision::CameraConfig camera_;
  std::string name_;
  std::FILE* log_;
  std::unique_ptr<models::vision::Tracker> tracker_;
  adapters::vision::Frame frame_;
  std::vector<MarkerPose> poses_;
  bool has_frame_ = false, ended_ = false;
  runtime::Window read_ms_{1 << 16}, track_ms_{1 << 16}, trans_pct_{1 << 16}, rot_deg_{1 << 16}, reg_px_{1 << 16};
  std::uint64_t frames_ = 0, with_tag_ = 0, detections_ = 0, refused_ = 0, unreadable_ = 0, skipped_ = 0;
};

}  // namespace hcosim::services::tracker
