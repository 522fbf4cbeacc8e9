// Camera sources: where the tracker's frames come from. An image folder
// (files sorted by name), a video file, or a live V4L2 camera, all through
// OpenCV in the capture module (vision/capture.h), loaded by the first of
// them opened; and the synthetic camera, whose every frame has a known pose.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "models/vision/synthetic.h"

namespace hcosim::adapters::vision {

struct Frame {
  cv::Mat image;                // CV_8UC1 grey or CV_8UC3 BGR; empty when `problem` says why
  std::uint64_t index = 0;      // position in the source, from 0
  std::int64_t capture_ns = 0;  // steady clock when the frame was captured or read, ns
  std::string problem;          // why this frame has no image (e.g. a file that does not decode)
};

class Source {
 public:
  virtual ~Source() = default;
  // The next frame; false at the end of a finite source, or when a live
  // camera stops delivering. A frame that cannot be read comes back with
  // an empty image and `problem` set; the source goes on after it.
  virtual bool next(Frame& f) = 0;
  // Where the frames come from, for messages: "folder frames/: 200 images".
  virtual std::string describe() const = 0;
  // Back to frame 0; false for a source that cannot (a live camera).
  virtual bool rewind() = 0;
};

// The images of a folder, in file-name order; files whose extension is
// not an image format OpenCV reads are ignored. Throws std::runtime_error
// when the folder cannot be read or holds no image.
std::unique_ptr<Source> open_folder(const std::string& path);

// A video file. Throws std::runtime_error when OpenCV cannot open it.
std::unique_ptr<Source> open_video(const std::string& path);

// open_folder for a folder, open_video for anything else.
std::unique_ptr<Source> open_path(const std::string& path);

// A live camera, "/dev/videoN", asking it for width x height at fps (0:
// the camera's own). Throws std::runtime_error saying why it cannot be
// opened (missing, no permission, busy) or when it delivers no frame.
std::unique_ptr<Source> open_v4l2(const std::string& device, int width, int height, double fps);

// The synthetic camera moving along orbit(t, path): frame i at time
// i / rate_hz. Endless when frames is 0.
class SyntheticSource : public Source {
 public:
  // Throws std::invalid_argument for a rate <= 0 or a bad path.
  SyntheticSource(const models::vision::SyntheticCamera& camera, const models::vision::Conditions& conditions,
                  double rate_hz, std::uint64_t frames = 0, const models::vision::Orbit& path = {});
  bool next(Frame& f) override;
  std::string describe() const override;
  bool rewind() override;

  // The true pose of the tag in the camera in frame i.
  Eigen::Isometry3d truth(std::uint64_t index) const;
  const models::vision::SyntheticCamera& camera() const { return camera_; }

 private:
  models::vision::SyntheticCamera camera_;
  models::vision::Conditions conditions_;
  double rate_hz_;
  std::uint64_t frames_, next_ = 0;
  models::vision::Orbit path_;
};

}  // namespace hcosim::adapters::vision
