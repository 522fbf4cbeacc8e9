// The AR view's params (docs/arview.md) read into what it draws and
// writes: the scene's objects, the marker and camera it registers by, the
// view's scale, and its video, pictures and plots.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "adapters/config.h"
#include "adapters/device/device_config.h"
#include "adapters/scene.h"

namespace hcosim::adapters::render {

// One object drawn over the frames.
struct ViewItem {
  std::string name;
  std::string kind;  // rigid or deformable
  double size = 0;   // rigid: half-edge or radius, m (the rigid service's default when absent)
  cv::Scalar colour;
};

struct ViewConfig {
  std::string camera;                           // whose frames and poses ("": any)
  int tag_id = 0;                               // the marker the scene stands on
  std::string device = device::kDefaultDevice;  // whose stylus is drawn
  std::vector<ViewItem> items;
  std::string video = "ar.mp4";   // in the output folder; "" none
  std::vector<double> snapshots;  // s of simulated time, ascending: a picture each
  bool plots = true;              // force and penetration plots at the end
  bool stylus = true;             // draw the stylus
  double force_scale = 0.02;      // m of arrow per N
  double fps = 0;                 // the video's frame rate
};

// `rate_hz`: the service's rate, the video's frame rate unless `fps` says.
// `marker`: the scene's, whose id is the view's unless the params give
// `tag_id`.
// Throws adapters::ConfigError at FILE:LINE:COL for an unknown key or a
// value out of range.
ViewConfig view_config(const Config& params, double rate_hz, const MarkerSpec& marker = {});

}  // namespace hcosim::adapters::render
