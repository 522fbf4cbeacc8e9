// The media module (media_module.h): OpenCV's image files, video files and
// V4L2 cameras, built as build/bin/hcosim_adapters_vision_media.so.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "adapters/vision/media_module.h"

namespace hcosim::adapters::vision {
namespace {

namespace fs = std::filesystem;

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Extensions of the image formats Debian's OpenCV reads.
bool is_image(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const char* x : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".pgm", ".ppm", ".pbm", ".pnm", ".webp"})
    if (e == x) return true;
  return false;
}

class Folder : public Source {
 public:
  Folder(std::string path, std::vector<fs::path> files, std::size_t ignored)
      : path_(std::move(path)), files_(std::move(files)), ignored_(ignored) {}

  bool next(Frame& f) override {
    if (next_ >= files_.size()) return false;
    f = Frame{};
    f.index = next_;
    const fs::path& file = files_[next_++];
    // ANYCOLOR keeps grey files grey; every depth is read as 8 bits.
    f.image = cv::imread(file.string(), cv::IMREAD_ANYCOLOR);
    f.capture_ns = now_ns();
    if (f.image.empty()) f.problem = file.string() + ": cannot be read as an image";
    return true;
  }
  std::string describe() const override {
    return "folder " + path_ + ": " + std::to_string(files_.size()) + " images" +
           (ignored_ ? ", " + std::to_string(ignored_) + " other files ignored" : "");
  }
  bool rewind() override { return next_ = 0, true; }

 private:
  std::string path_;
  std::vector<fs::path> files_;
  std::size_t ignored_;
  std::size_t next_ = 0;
};

// A video file or a live camera, through cv::VideoCapture.
class Capture : public Source {
 public:
  Capture(std::string what, cv::VideoCapture cap, bool live)
      : what_(std::move(what)), cap_(std::move(cap)), live_(live) {}

  bool next(Frame& f) override {
    f = Frame{};
    if (!cap_.read(f.image) || f.image.empty()) return false;
    f.capture_ns = now_ns();
    f.index = next_++;
    return true;
  }
  std::string describe() const override { return what_; }
  bool rewind() override {
    if (live_ || !cap_.set(cv::CAP_PROP_POS_FRAMES, 0)) return false;
    next_ = 0;
    return true;
  }

 private:
  std::string what_;
  cv::VideoCapture cap_;
  bool live_;
  std::uint64_t next_ = 0;
};

// The module's entry points (media_module.h), reached only through
// hcosim_media_api(): of internal linkage, so that a same-named function of
// the executable that loaded the module (exported by services/ for its
// stacks) can never stand in for them.

Source* capture_folder(const std::string& path) {
  std::error_code ec;
  std::vector<fs::path> files;
  std::size_t ignored = 0;
  for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    if (is_image(it->path()))
      files.push_back(it->path());
    else
      ++ignored;
  }
  if (ec) throw std::runtime_error(path + ": the folder cannot be read: " + ec.message());
  if (files.empty()) throw std::runtime_error(path + ": the folder holds no image (.png, .jpg, .bmp, .tif, .pgm, ...)");
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename().string() < b.filename().string(); });
  return new Folder(path, std::move(files), ignored);
}

Source* capture_video(const std::string& path) {
  if (!fs::exists(path)) throw std::runtime_error(path + ": no such file or folder");
  if (access(path.c_str(), R_OK) != 0) throw std::runtime_error(path + ": permission denied");
  // FFmpeg reads every common container; GStreamer, the other file
  // reader, is tried quietly after it, so a file nobody reads gives one
  // message, ours. (CAP_ANY would also probe cameras: gphoto2's USB
  // autodetect, which leaks, for a file.)
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  if (!cap.isOpened()) {
    const auto level = cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    cap.open(path, cv::CAP_GSTREAMER);
    cv::utils::logging::setLogLevel(level);
  }
  if (!cap.isOpened())
    throw std::runtime_error(path + ": OpenCV cannot open it as a video (not a video, or a codec this build lacks)");
  const double n = cap.get(cv::CAP_PROP_FRAME_COUNT), fps = cap.get(cv::CAP_PROP_FPS);
  std::string what = "video " + path;
  if (n > 0) what += ": about " + std::to_string(std::int64_t(n)) + " frames";
  if (fps > 0) what += (n > 0 ? " at " : ": ") + cv::format("%.3g fps", fps);
  return new Capture(what, std::move(cap), false);
}

Source* capture_v4l2(const std::string& device, int width, int height, double fps) {
  if (!fs::exists(device)) throw std::runtime_error("V4L2 camera " + device + ": no such device");
  if (access(device.c_str(), R_OK | W_OK) != 0)
    throw std::runtime_error("V4L2 camera " + device + ": permission denied (is this user in the group 'video'?)");
  cv::VideoCapture cap(device, cv::CAP_V4L2);
  if (!cap.isOpened())
    throw std::runtime_error("V4L2 camera " + device + ": cannot be opened (not a capture device, or busy)");
  if (width > 0) cap.set(cv::CAP_PROP_FRAME_WIDTH, width), cap.set(cv::CAP_PROP_FRAME_HEIGHT, height);
  if (fps > 0) cap.set(cv::CAP_PROP_FPS, fps);
  cv::Mat probe;
  if (!cap.read(probe) || probe.empty()) throw std::runtime_error("V4L2 camera " + device + ": delivers no frame");
  if (width > 0 && (probe.cols != width || probe.rows != height))
    throw std::runtime_error("V4L2 camera " + device + ": asked for " + std::to_string(width) + "x" +
                             std::to_string(height) + ", it gives " + std::to_string(probe.cols) + "x" +
                             std::to_string(probe.rows));
  const std::string what = "V4L2 camera " + device + ": " + std::to_string(probe.cols) + "x" +
                           std::to_string(probe.rows) + cv::format(" at %.3g fps", cap.get(cv::CAP_PROP_FPS));
  return new Capture(what, std::move(cap), true);
}

void write_image(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw std::runtime_error("cannot write the image " + path);
}

std::vector<unsigned char> encode_jpeg(const cv::Mat& image, int quality) {
  std::vector<unsigned char> out;
  if (!cv::imencode(".jpg", image, out, {cv::IMWRITE_JPEG_QUALITY, quality}))
    throw std::runtime_error("cannot encode an image as JPEG");
  return out;
}

void* open_video_out(const std::string& path, const char fourcc[4], double fps, cv::Size size) {
  auto v = std::make_unique<cv::VideoWriter>(path, cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]),
                                             fps, size);
  if (!v->isOpened())
    throw std::runtime_error("cannot write the video " + path + " (OpenCV has no " + std::string(fourcc, 4) +
                             " encoder, or the folder is not writable)");
  return v.release();
}

void write_video_out(void* video, const cv::Mat& frame) { static_cast<cv::VideoWriter*>(video)->write(frame); }

void close_video_out(void* video) { delete static_cast<cv::VideoWriter*>(video); }

}  // namespace
}  // namespace hcosim::adapters::vision

extern "C" const hcosim::adapters::vision::MediaApi* hcosim_media_api() {
  using namespace hcosim::adapters::vision;
  static const MediaApi api{kMediaApiVersion, capture_folder, capture_video,   capture_v4l2,   write_image,
                            encode_jpeg,      open_video_out, write_video_out, close_video_out};
  return &api;
}
