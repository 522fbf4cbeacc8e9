#include "adapters/vision/calibration.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <opencv2/core/persistence.hpp>

#include "adapters/config.h"

namespace hcosim::adapters::vision {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The numbers of an rows x cols matrix: an !!opencv-matrix or a plain map
// with rows, cols and data.
std::vector<double> matrix(const Config& root, const std::string& key, int rows, int max_cols) {
  if (!root.has(key) || !root.node()[key].IsMap())
    root.fail(key, "'" + key + "' must be a matrix with rows, cols and data");
  const Config m = root.map(key);
  m.require({"rows", "cols", "data"}, "'" + key + "'");
  const double r = m.number("rows", 0, -kInf, kInf), c = m.number("cols", 0, -kInf, kInf);
  // Distortion is written as 1 x n or n x 1. Sizes are checked whole and
  // small before they are multiplied (a fuzzed 4e13 x 3 overflowed an int).
  const bool small = r == std::floor(r) && c == std::floor(c) && r >= 1 && c >= 1 && r <= 8 && c <= 8;
  const int n = small ? int(r) * int(c) : 0;
  if (rows == 3 ? (r != 3 || c != 3) : ((r != 1 && c != 1) || n < 4 || n > max_cols))
    m.fail("rows", rows == 3 ? "'" + key + "' must be 3x3"
                             : "'" + key +
                                   "' must hold 4 or 5 coefficients (k1 k2 p1 p2 [k3]); hcosim does not "
                                   "model the rational or thin-prism terms");
  const std::vector<double> out = m.numbers("data", -kInf, kInf);
  if (int(out.size()) != n)
    m.fail("data",
           "'" + key + ".data' holds " + std::to_string(out.size()) + " numbers, rows x cols is " + std::to_string(n));
  return out;
}

}  // namespace

models::vision::Intrinsics read_intrinsics(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot be read");
  // OpenCV writes the directive "%YAML:1.0", which YAML 1.2 parsers refuse;
  // it is blanked, keeping line numbers.
  std::stringstream text;
  std::string line;
  for (bool first = true; std::getline(in, line); first = false)
    text << (first && line.rfind("%YAML:", 0) == 0 ? "" : line) << '\n';
  const Config root = Config::parse(text.str(), path,
                                    "a camera calibration (camera_matrix and distortion_coefficients, OpenCV's "
                                    "calibration format)");
  if (!root.has("camera_matrix")) throw ConfigError(path + ": no 'camera_matrix'");
  const std::string model = root.string("distortion_model", "plumb_bob");
  if (model != "plumb_bob" && model != "radtan")
    root.fail("distortion_model", "distortion_model '" + model + "': hcosim models plumb_bob (k1 k2 p1 p2 k3) only");
  models::vision::Intrinsics k;
  // The size is checked with the rest by check() below.
  k.width = root.whole("image_width", 0, 1, 100000);
  k.height = root.whole("image_height", 0, 1, 100000);
  const std::vector<double> m = matrix(root, "camera_matrix", 3, 3);
  k.fx = m[0], k.cx = m[2], k.fy = m[4], k.cy = m[5];
  if (!(k.fx > 0 && k.fy > 0) || m[1] != 0 || m[3] != 0 || m[6] != 0 || m[7] != 0 || m[8] != 1)
    root.map("camera_matrix")
        .fail("data", "'camera_matrix' must be [fx 0 cx; 0 fy cy; 0 0 1] with fx, fy > 0 (no skew)");
  if (root.has("distortion_coefficients")) {
    const std::vector<double> d = matrix(root, "distortion_coefficients", 1, 5);
    for (std::size_t i = 0; i < d.size(); ++i) k.distortion[i] = d[i];
  }
  if ((k.width == 0) != (k.height == 0))
    throw ConfigError(path + ": give both image_width and image_height, or neither");
  try {
    // Without a size, the rest is checked at any valid size.
    models::vision::Intrinsics sized = k;
    if (!k.width) sized.width = sized.height = 16;
    models::vision::check(sized);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(path + ": " + e.what());
  }
  return k;
}

void write_intrinsics(const std::string& path, const models::vision::Intrinsics& k) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw std::runtime_error(path + ": cannot be written");
  fs << "image_width" << k.width << "image_height" << k.height;
  fs << "camera_matrix" << cv::Mat(models::vision::camera_matrix(k));
  fs << "distortion_coefficients" << models::vision::distortion(k);
}

models::vision::Intrinsics with_frame_size(models::vision::Intrinsics k, int width, int height,
                                           const std::string& path) {
  if (k.width == 0 || k.height == 0) {
    k.width = width, k.height = height;
    check(k);
    return k;
  }
  if (k.width != width || k.height != height)
    throw std::invalid_argument(path + ": calibrated at " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                                ", but the frames are " + std::to_string(width) + "x" + std::to_string(height) +
                                " (intrinsics hold for one frame size: calibrate at this size)");
  return k;
}

}  // namespace hcosim::adapters::vision
