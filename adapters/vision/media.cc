#include "adapters/vision/media.h"

#include <dlfcn.h>

#include <stdexcept>

#include "adapters/vision/media_module.h"

namespace hcosim::adapters::vision {

// Its path is fixed at build time (HCOSIM_MEDIA_MODULE, in the build's bin/).
const MediaApi& media_module() {
  static const MediaApi* api = [] {
    const std::string path = HCOSIM_MEDIA_MODULE;
    void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) throw std::runtime_error("images and video: cannot load " + path + ": " + dlerror());
    auto entry = reinterpret_cast<const MediaApi* (*)()>(dlsym(lib, "hcosim_media_api"));
    if (!entry) throw std::runtime_error(path + " has no hcosim_media_api");
    const MediaApi* a = entry();
    if (a->version != kMediaApiVersion) throw std::runtime_error(path + " is from another build of hcosim; rebuild");
    return a;
  }();
  return *api;
}

void load_media() { media_module(); }

void write_image(const std::string& path, const cv::Mat& image) { media_module().write_image(path, image); }

std::vector<unsigned char> encode_jpeg(const cv::Mat& image, int quality) {
  return media_module().encode_jpeg(image, quality);
}

VideoOut::VideoOut(const std::string& path, const std::string& fourcc, double fps, cv::Size size) {
  if (fourcc.size() != 4)
    throw std::invalid_argument("video " + path + ": a codec has four characters, not '" + fourcc + "'");
  video_ = media_module().open_video_out(path, fourcc.c_str(), fps, size);
}

VideoOut::~VideoOut() { media_module().close_video_out(video_); }

void VideoOut::write(const cv::Mat& frame) { media_module().write_video_out(video_, frame); }

}  // namespace hcosim::adapters::vision
