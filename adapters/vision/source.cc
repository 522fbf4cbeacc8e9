#include "adapters/vision/source.h"

#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "adapters/vision/media_module.h"

namespace hcosim::adapters::vision {
namespace {

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

std::unique_ptr<Source> open_folder(const std::string& path) {
  return std::unique_ptr<Source>(media_module().folder(path));
}

std::unique_ptr<Source> open_video(const std::string& path) {
  return std::unique_ptr<Source>(media_module().video(path));
}

std::unique_ptr<Source> open_path(const std::string& path) {
  return std::filesystem::is_directory(path) ? open_folder(path) : open_video(path);
}

std::unique_ptr<Source> open_v4l2(const std::string& device, int width, int height, double fps) {
  return std::unique_ptr<Source>(media_module().v4l2(device, width, height, fps));
}

SyntheticSource::SyntheticSource(const models::vision::SyntheticCamera& camera,
                                 const models::vision::Conditions& conditions, double rate_hz, std::uint64_t frames,
                                 const models::vision::Orbit& path)
    : camera_(camera), conditions_(conditions), rate_hz_(rate_hz), frames_(frames), path_(path) {
  if (!(rate_hz > 0 && rate_hz <= 1e4)) throw std::invalid_argument("synthetic camera: rate must be in (0, 1e4] Hz");
  models::vision::check(path);
}

bool SyntheticSource::next(Frame& f) {
  if (frames_ && next_ >= frames_) return false;
  f = Frame{};
  f.index = next_++;
  // The frame's seed is its index: a sequence renders the same every run.
  f.image = camera_.render(truth(f.index), conditions_, f.index);
  f.capture_ns = now_ns();
  return true;
}

std::string SyntheticSource::describe() const {
  const models::vision::Intrinsics& k = camera_.intrinsics();
  return "synthetic camera: " + std::to_string(k.width) + "x" + std::to_string(k.height) + " at " +
         cv::format("%.3g", rate_hz_) + " Hz, " + camera_.marker().family + " id " +
         std::to_string(camera_.marker().id) + (frames_ ? ", " + std::to_string(frames_) + " frames" : "");
}

bool SyntheticSource::rewind() { return next_ = 0, true; }

Eigen::Isometry3d SyntheticSource::truth(std::uint64_t index) const {
  return models::vision::orbit(double(index) / rate_hz_, path_);
}

}  // namespace hcosim::adapters::vision
