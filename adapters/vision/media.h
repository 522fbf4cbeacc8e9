// Image and video files written through the media module
// (media_module.h), so that a process links none of OpenCV's codecs.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace hcosim::adapters::vision {

// Loads the media module now instead of at the first image or video: its
// codecs' libraries (OpenCV's, and GDAL's behind them) take a burst of CPU
// to load, which a live stream should spend before its first frame.
// Throws std::runtime_error as the first image would.
void load_media();

// Writes an 8-bit grey or BGR image, its format from the extension.
// Throws std::runtime_error naming the path when it cannot.
void write_image(const std::string& path, const cv::Mat& image);

// `image` (8-bit grey or BGR) as a JPEG file's bytes, `quality` 0..100.
std::vector<unsigned char> encode_jpeg(const cv::Mat& image, int quality);

// A video file being written, every frame of one size (BGR, 8 bits).
class VideoOut {
 public:
  // `fourcc`: the codec's four characters, e.g. "mp4v". Throws
  // std::runtime_error when the file cannot be opened for that codec.
  VideoOut(const std::string& path, const std::string& fourcc, double fps, cv::Size size);
  ~VideoOut();
  VideoOut(const VideoOut&) = delete;
  VideoOut& operator=(const VideoOut&) = delete;

  void write(const cv::Mat& frame);

 private:
  void* video_;
};

}  // namespace hcosim::adapters::vision
