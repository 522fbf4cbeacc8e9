#include "models/vision/synthetic.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace hcosim::models::vision {

namespace {

constexpr int kSupersample = 3;
constexpr int kTexelsPerCell = 32;
constexpr double kBackground = 90, kWhite = 230, kBlack = 25;  // grey levels

// Tag frame (x right, y up, z toward the camera) to camera frame, facing.
const Eigen::Matrix3d kFacing = Eigen::Vector3d(1, -1, -1).asDiagonal();

}  // namespace

Conditions condition(const std::string& name) {
  Conditions c;
  if (name == "clean") return c;
  if (name == "noisy") return c.noise = 6, c;
  if (name == "blurred") return c.blur = 1.2, c;
  throw std::invalid_argument("condition '" + name + "' is not one of clean, noisy, blurred");
}

SyntheticCamera::SyntheticCamera(const Intrinsics& k, const Marker& m) : k_(k), m_(m) {
  check(k);
  if (!(m.tag_size > 0.001 && m.tag_size < 2)) throw std::invalid_argument("marker: tag_size must be in (0.001, 2) m");
  if (!(m.sheet >= 1.25 && m.sheet <= 10)) throw std::invalid_argument("marker: sheet must be in [1.25, 10] tag sizes");
  const Family family(m.family);
  const cv::Mat tag = family.image(m.id);
  // The sheet: white, the tag (with its own white margin) at its centre.
  const int sheet_cells = int(std::ceil(m.sheet * family.border_cells() / 2.0)) * 2;
  const int cells = std::max(sheet_cells, family.total_cells() + (family.total_cells() % 2));
  texture_ = cv::Mat(cells * kTexelsPerCell, cells * kTexelsPerCell, CV_8U, cv::Scalar(kWhite));
  cv::Mat big;
  cv::resize(tag, big, cv::Size(), kTexelsPerCell, kTexelsPerCell, cv::INTER_NEAREST);
  big.convertTo(big, CV_8U, (kWhite - kBlack) / 255.0, kBlack);
  const int at = (texture_.cols - big.cols) / 2;
  big.copyTo(texture_(cv::Rect(at, at, big.cols, big.rows)));
  metres_per_texel_ = m.tag_size / family.border_cells() / kTexelsPerCell;
  bool distorted = false;
  for (double d : k.distortion) distorted |= d != 0;
  if (distorted) {
    // Each image pixel takes the undistorted render's value where the
    // pixel's ray lands without distortion.
    std::vector<cv::Point2f> px;
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) px.emplace_back(float(x), float(y));
    std::vector<cv::Point2f> ideal;
    cv::undistortPoints(px, ideal, camera_matrix(k), distortion(k), cv::noArray(), camera_matrix(k));
    map_x_.create(k.height, k.width, CV_32F), map_y_.create(k.height, k.width, CV_32F);
    for (int y = 0, i = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x, ++i) map_x_.at<float>(y, x) = ideal[i].x, map_y_.at<float>(y, x) = ideal[i].y;
  }
}

cv::Rect SyntheticCamera::footprint(const Eigen::Matrix3d& H) const {
  const cv::Rect whole(0, 0, k_.width, k_.height);
  // A texel's bilinear reach is one texel past the texture's edge.
  const double w = texture_.cols, hgt = texture_.rows;
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(w, -1, 1), Eigen::Vector3d(w, hgt, 1),
                                   Eigen::Vector3d(-1, hgt, 1)}) {
    const Eigen::Vector3d q = H * c;
    // A sheet reaching behind the camera has no bounded footprint.
    if (!(q.z() > 1e-9)) return whole;
    x0 = std::min(x0, q.x() / q.z()), x1 = std::max(x1, q.x() / q.z());
    y0 = std::min(y0, q.y() / q.z()), y1 = std::max(y1, q.y() / q.z());
  }
  // Supersampled pixels, one more on each side, then whole output pixels.
  const double ss = kSupersample;
  const double lx = std::floor((x0 - 1) / ss), ly = std::floor((y0 - 1) / ss);
  const double hx = std::ceil((x1 + 2) / ss), hy = std::ceil((y1 + 2) / ss);
  const auto clamp = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
  const int ax = clamp(lx, k_.width), ay = clamp(ly, k_.height), bx = clamp(hx, k_.width), by = clamp(hy, k_.height);
  return cv::Rect(ax, ay, bx - ax, by - ay) & whole;
}

cv::Mat SyntheticCamera::render(const Eigen::Isometry3d& pose, const Conditions& c, std::uint64_t seed) const {
  if (!pose.matrix().allFinite() || pose.translation().z() <= 0)
    throw std::invalid_argument("synthetic camera: the tag must be finite and in front of the camera");
  // texel -> tag plane (m) -> ideal image -> supersampled image, whose
  // pixel centres sit at ss x + (ss - 1) / 2.
  const double m = metres_per_texel_, half = 0.5 * texture_.cols;
  const Eigen::Matrix3d A = (Eigen::Matrix3d() << m, 0, m * (0.5 - half), 0, -m, m * (half - 0.5), 0, 0, 1).finished();
  Eigen::Matrix3d P;
  P << pose.linear().col(0), pose.linear().col(1), pose.translation();
  const Eigen::Matrix3d K = (Eigen::Matrix3d() << k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1).finished();
  const double ss = kSupersample, o = 0.5 * (ss - 1);
  const Eigen::Matrix3d T = (Eigen::Matrix3d() << ss, 0, o, 0, ss, o, 0, 0, 1).finished();
  const Eigen::Matrix3d H = T * K * P * A;
  cv::Mat frame(k_.height, k_.width, CV_8U, cv::Scalar(kBackground));
  // Only the sheet's footprint is warped and averaged down: the rest of
  // the frame is background, which a warp of the whole supersampled frame
  // would compute at every frame for nothing. The footprint is aligned to
  // whole output pixels, so each averaged block is the same as in a full
  // warp.
  const cv::Rect out = footprint(H);
  if (!out.empty()) {
    const cv::Rect in(out.x * kSupersample, out.y * kSupersample, out.width * kSupersample, out.height * kSupersample);
    const Eigen::Matrix3d shift = (Eigen::Matrix3d() << 1, 0, -in.x, 0, 1, -in.y, 0, 0, 1).finished();
    const Eigen::Matrix3d Hs = shift * H;
    cv::Matx33d h;
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) h(r, col) = Hs(r, col);
    cv::Mat big;
    cv::warpPerspective(texture_, big, h, in.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(kBackground));
    cv::resize(big, frame(out), out.size(), 0, 0, cv::INTER_AREA);
  }
  if (!map_x_.empty()) {
    cv::Mat distorted;
    cv::remap(frame, distorted, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(kBackground));
    frame = distorted;
  }
  if (c.occlusion > 0) {
    // A bar lying over the tag's left part, reaching past the sheet.
    const double s = m_.tag_size, left = -0.5 * s * m_.sheet * 1.2, right = -0.5 * s + c.occlusion * s;
    std::vector<cv::Point> poly;
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(left, -0.3 * s, 0), Eigen::Vector3d(right, -0.3 * s, 0),
                                     Eigen::Vector3d(right, 0.3 * s, 0), Eigen::Vector3d(left, 0.3 * s, 0)}) {
      const Eigen::Vector2d q = project(k_, pose, p);
      poly.emplace_back(int(std::lround(q.x())), int(std::lround(q.y())));
    }
    cv::fillConvexPoly(frame, poly, cv::Scalar(160), cv::LINE_AA);
  }
  if (c.blur > 0) cv::GaussianBlur(frame, frame, cv::Size(), c.blur);
  cv::Mat f;
  frame.convertTo(f, CV_32F, c.gain, c.offset);
  if (c.gradient != 0) {
    for (int y = 0; y < f.rows; ++y) {
      float* row = f.ptr<float>(y);
      for (int x = 0; x < f.cols; ++x) row[x] += float(c.gradient * (double(x) / f.cols - 0.5) * 255);
    }
  }
  if (c.noise > 0) {
    cv::Mat n(f.size(), CV_32F);
    cv::RNG rng(seed * 2654435761u + 1);
    rng.fill(n, cv::RNG::NORMAL, 0, c.noise);
    f += n;
  }
  f.convertTo(frame, CV_8U);  // rounds and saturates
  return frame;
}

std::vector<Eigen::Vector2d> SyntheticCamera::corners(const Eigen::Isometry3d& pose) const {
  const double h = 0.5 * m_.tag_size;
  std::vector<Eigen::Vector2d> out;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(-h, -h, 0), Eigen::Vector3d(h, -h, 0), Eigen::Vector3d(h, h, 0), Eigen::Vector3d(-h, h, 0)})
    out.push_back(project(k_, pose, p));
  return out;
}

Eigen::Isometry3d facing(double distance) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = kFacing;
  p.translation() = Eigen::Vector3d(0, 0, distance);
  return p;
}

std::vector<Eigen::Isometry3d> random_poses(const Intrinsics& k, double tag_size, int n, std::uint64_t seed,
                                            double near, double far, double max_tilt_deg) {
  check(k);
  if (!(near > 0 && far >= near && max_tilt_deg >= 0 && max_tilt_deg < 90 && n >= 0))
    throw std::invalid_argument("random_poses: need 0 < near <= far and a tilt in [0, 90)");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const double pi = std::acos(-1.0), h = 0.5 * tag_size;
  std::vector<Eigen::Isometry3d> out;
  for (int tries = 0; int(out.size()) < n; ++tries) {
    if (tries > 1000 * (n + 1))
      throw std::invalid_argument("random_poses: the tag does not fit in the frame at these distances");
    const double d = near + (far - near) * unit(rng);
    const double tilt = max_tilt_deg * pi / 180 * unit(rng), axis = 2 * pi * unit(rng), turn = 2 * pi * unit(rng);
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = kFacing *
                 Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)).toRotationMatrix() *
                 Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // The centre along a ray through a random pixel.
    const double u = k.width * unit(rng), v = k.height * unit(rng);
    p.translation() = d * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1).normalized();
    bool inside = true;
    for (const Eigen::Vector3d& c :
         {Eigen::Vector3d(-h, -h, 0), Eigen::Vector3d(h, -h, 0), Eigen::Vector3d(h, h, 0), Eigen::Vector3d(-h, h, 0)}) {
      const Eigen::Vector3d q = p * c;
      const double x = k.fx * q.x() / q.z() + k.cx, y = k.fy * q.y() / q.z() + k.cy;
      inside &= q.z() > 0 && x >= 8 && y >= 8 && x <= k.width - 9 && y <= k.height - 9;
    }
    if (inside) out.push_back(p);
  }
  return out;
}

void check(const Orbit& o) {
  if (!(o.distance > 0 && o.distance <= 100)) throw std::invalid_argument("orbit: distance must be in (0, 100] m");
  if (!(o.swing >= 0 && o.swing < o.distance)) throw std::invalid_argument("orbit: swing must be in [0, distance)");
  if (!(o.tilt_deg >= 0 && o.base_tilt_deg >= 0 && o.base_tilt_deg + o.tilt_deg < 80))
    throw std::invalid_argument("orbit: tilt_deg and base_tilt_deg must be >= 0 with a sum under 80 degrees");
  if (!(o.period > 0 && o.period <= 1e6)) throw std::invalid_argument("orbit: period must be in (0, 1e6] s");
  if (!(o.sweep_deg >= 0 && o.sweep_deg < 180)) throw std::invalid_argument("orbit: sweep_deg must be in [0, 180)");
}

Eigen::Isometry3d orbit(double t, const Orbit& o) {
  const double pi = std::acos(-1.0), phase = 2 * pi * t / o.period;
  const double d = o.distance + o.swing * std::sin(phase);
  const double tilt = (o.base_tilt_deg + o.tilt_deg * std::sin(0.5 * phase)) * pi / 180;
  if (o.upright) {
    // Look-at from the camera's place, image up toward the tag's +z
    // (OpenCV camera: x right, y down, z forward).
    const double azimuth = (-90 + o.sweep_deg * std::sin(phase)) * pi / 180;
    const Eigen::Vector3d c =
        d * Eigen::Vector3d(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    const Eigen::Vector3d forward = -c.normalized();
    // Straight down (tilt 0) the image's up is the tag's +y instead.
    const Eigen::Vector3d up = tilt > 1e-6 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d right = forward.cross(up).normalized(), down = forward.cross(right);
    Eigen::Matrix3d camera_in_tag;
    camera_in_tag << right, down, forward;
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = camera_in_tag.transpose();
    p.translation() = -camera_in_tag.transpose() * c;
    return p;
  }
  Eigen::Isometry3d p = facing(d);
  p.linear() =
      kFacing * Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(phase), std::sin(phase), 0)).toRotationMatrix();
  return p;
}

double registration_error_px(const Intrinsics& k, const Eigen::Isometry3d& estimated, const Eigen::Isometry3d& truth,
                             const std::vector<Eigen::Vector3d>& points) {
  double worst = 0;
  for (const Eigen::Vector3d& p : points)
    worst = std::max(worst, (project(k, estimated, p) - project(k, truth, p)).norm());
  return worst;
}

}  // namespace hcosim::models::vision
