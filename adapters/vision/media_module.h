// The interface between the media module (media_module.cc, built as
// build/bin/hcosim_adapters_vision_media.so) and its one loader, media_module(): OpenCV's
// image files, video files and V4L2 cameras, whose libraries bring some
// 230 shared libraries (FFmpeg, GStreamer, GDAL, ...) whose loading was
// half of a tracker's start when idle, more beside the scene
// (docs/reliability.md, "Faults"). A process loads them the
// first time it reads or writes an image or a video; a synthetic camera
// never does. Each function throws std::runtime_error saying what failed.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "adapters/vision/source.h"

namespace hcosim::adapters::vision {

// Bumped when MediaApi changes, so that a module of another build is refused.
constexpr int kMediaApiVersion = 2;

struct MediaApi {
  int version;
  // The sources of source.h, each new, owned by the caller.
  Source* (*folder)(const std::string& path);
  Source* (*video)(const std::string& path);
  Source* (*v4l2)(const std::string& device, int width, int height, double fps);
  // An image file, its format from the extension.
  void (*write_image)(const std::string& path, const cv::Mat& image);
  // An image in memory as JPEG, `quality` 0..100.
  std::vector<unsigned char> (*encode_jpeg)(const cv::Mat& image, int quality);
  // A video being written: opened (a handle), given frames, closed.
  void* (*open_video_out)(const std::string& path, const char fourcc[4], double fps, cv::Size size);
  void (*write_video_out)(void* video, const cv::Mat& frame);
  void (*close_video_out)(void* video);
};

// The module, loaded once, on first use. Throws std::runtime_error when it
// cannot be loaded or is from another build.
const MediaApi& media_module();

}  // namespace hcosim::adapters::vision
