#include "services/tracker/frame_tracker.h"

#include <cmath>

#include "adapters/validate.h"
#include "adapters/vision/calibration.h"
#include "adapters/vision/vision_idl.h"
#include "models/vision/pose.h"
#include "models/vision/synthetic.h"
#include "services/runtime/service.h"

namespace hcosim::services::tracker {

FrameTracker::FrameTracker(adapters::vision::CameraConfig camera, std::string name, std::FILE* log)
    : camera_(std::move(camera)), name_(std::move(name)), log_(log) {}

bool FrameTracker::step(const StepStamp& stamp) {
  poses_.clear();
  has_frame_ = false;
  if (ended_) return false;
  const std::unique_ptr<adapters::vision::Source>& source = camera_.source;
  const std::int64_t r0 = runtime::mono_ns();
  const bool got = source->next(frame_) || (camera_.loop && source->rewind() && source->next(frame_));
  read_ms_.add((runtime::mono_ns() - r0) * 1e-6);
  if (!got) {
    std::fprintf(log_, "%s: the source ended after %llu frames\n", name_.c_str(), (unsigned long long)frames_);
    std::fflush(log_);
    ended_ = true;
    return false;
  }
  ++frames_;
  const adapters::vision::Frame& f = frame_;
  if (!f.problem.empty()) {
    std::fprintf(stderr, "%s: frame %llu: %s, skipped\n", name_.c_str(), (unsigned long long)f.index,
                 f.problem.c_str());
    ++unreadable_;
    return true;
  }
  models::vision::Intrinsics& k = camera_.intrinsics;
  const models::vision::TrackerParams& tp = camera_.tracker;
  if (!tracker_) {
    k = adapters::vision::with_frame_size(k, f.image.cols, f.image.rows, camera_.intrinsics_file);
    tracker_ = std::make_unique<models::vision::Tracker>(tp, k);
  }
  if (f.image.cols != k.width || f.image.rows != k.height) {
    if (++skipped_ <= kNamedSkips)
      std::fprintf(stderr, "%s: frame %llu is %dx%d, not the calibrated %dx%d, skipped\n", name_.c_str(),
                   (unsigned long long)f.index, f.image.cols, f.image.rows, k.width, k.height);
    return true;
  }
  has_frame_ = true;
  const std::int64_t t0 = runtime::mono_ns();
  const std::vector<models::vision::Observation> seen = tracker_->track(f.image);
  track_ms_.add((runtime::mono_ns() - t0) * 1e-6);
  with_tag_ += !seen.empty();
  const adapters::vision::SyntheticSource* synthetic = camera_.synthetic;
  for (const models::vision::Observation& o : seen) {
    ++detections_;
    MarkerPose m = adapters::vision::marker_pose(name_, tp.detector.family, stamp, f.index, tp.tag_size, o,
                                                 (runtime::mono_ns() - f.capture_ns) * 1e-6);
    // A pose the subscribers would refuse (a degenerate fit) is not sent.
    if (adapters::validate(m)) {
      ++refused_;
      continue;
    }
    if (synthetic && o.detection.id == synthetic->camera().marker().id) {
      const Eigen::Isometry3d truth = synthetic->truth(f.index);
      trans_pct_.add(100 * (o.pose.tag_in_camera.translation() - truth.translation()).norm() /
                     truth.translation().norm());
      rot_deg_.add(models::vision::angle_between(o.pose.tag_in_camera.linear(), truth.linear()) * 180 / M_PI);
      reg_px_.add(models::vision::registration_error_px(k, o.pose.tag_in_camera, truth, camera_.scene));
    }
    poses_.push_back(m);
  }
  return true;
}

CameraFrame FrameTracker::frame(const StepStamp& stamp) const {
  return adapters::vision::camera_frame(name_, stamp, frame_.index, frame_.image, camera_.intrinsics);
}

void FrameTracker::report(std::FILE* out) const {
  std::fprintf(out,
               "%s: %llu frames, %llu with a tag, %llu detections; reading a frame p50 %.2f ms, detection and pose "
               "p50 %.2f ms p99 %.2f ms; %llu unreadable, %llu of another size, %llu poses refused\n",
               name_.c_str(), (unsigned long long)frames_, (unsigned long long)with_tag_,
               (unsigned long long)detections_, read_ms_.percentile(0.5), track_ms_.percentile(0.5),
               track_ms_.percentile(0.99), (unsigned long long)unreadable_, (unsigned long long)skipped_,
               (unsigned long long)(refused_ + (tracker_ ? tracker_->unposed() : 0)));
  if (camera_.synthetic && trans_pct_.size())
    std::fprintf(out,
                 "%s: against the synthetic truth: translation error p50 %.3f%% p95 %.3f%% of distance, rotation "
                 "error p50 %.3f deg p95 %.3f deg\n",
                 name_.c_str(), trans_pct_.percentile(0.5), trans_pct_.percentile(0.95), rot_deg_.percentile(0.5),
                 rot_deg_.percentile(0.95));
  if (camera_.synthetic && reg_px_.size())
    std::fprintf(out,
                 "%s: registration error (the sheet's corners and half its edge above them) p50 %.2f px p95 %.2f px "
                 "max %.2f px\n",
                 name_.c_str(), reg_px_.percentile(0.5), reg_px_.percentile(0.95), reg_px_.percentile(1));
}

}  // namespace hcosim::services::tracker
