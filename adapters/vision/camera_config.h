// The tracker service's params (docs/tracking.md) read into its camera
// source, the intrinsics its frames are taken with, and the tracker's
// parameters.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapters/config.h"
#include "adapters/scene.h"
#include "adapters/vision/source.h"
#include "models/vision/tracker.h"

namespace hcosim::adapters::vision {

struct CameraConfig {
  std::unique_ptr<Source> source;         // synthetic, an image folder, a video file or V4L2
  SyntheticSource* synthetic = nullptr;   // `source` when it is synthetic, else null
  models::vision::Intrinsics intrinsics;  // sized once the first frame is (0 x 0 until then for a file)
  std::string intrinsics_file;            // "" for a synthetic camera's own
  models::vision::TrackerParams tracker;
  std::vector<Eigen::Vector3d> scene;  // synthetic: where registration is measured, tag frame, m
  bool publish_frames = true;          // CameraFrame for the AR view
  bool loop = false;                   // a folder or video starts again at its end
};

// `rate_hz`: the service's rate, the synthetic and V4L2 cameras' frame
// rate. `marker`: the scene's, whose family, size and id are the tag's
// unless the params give `family`, `tag_size` and `tag_id`. Throws
// adapters::ConfigError at FILE:LINE:COL for an unknown key, a value out
// of range, or a source without its file.
CameraConfig camera_config(const Config& params, double rate_hz, const MarkerSpec& marker = {});

}  // namespace hcosim::adapters::vision
