#include "models/vision/detector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

extern "C" {
#include <apriltag/apriltag.h>
}

namespace hcosim::models::vision {

void check(const DetectorParams& p) {
  if (!(p.quad_decimate >= 1 && p.quad_decimate <= 8))
    throw std::invalid_argument("detector: quad_decimate must be in [1, 8]");
  if (!(p.quad_sigma >= -2 && p.quad_sigma <= 4))
    throw std::invalid_argument("detector: quad_sigma must be in [-2, 4]");
  if (p.nthreads < 1 || p.nthreads > 64) throw std::invalid_argument("detector: nthreads must be in [1, 64]");
  if (!(p.decode_sharpening >= 0 && p.decode_sharpening <= 2))
    throw std::invalid_argument("detector: decode_sharpening must be in [0, 2]");
  if (p.max_hamming < 0 || p.max_hamming > 3) throw std::invalid_argument("detector: max_hamming must be in [0, 3]");
}

namespace {

// Bilinear grey level at (x, y), pixel centres at integers; the caller
// keeps (x, y) at least one pixel inside the frame.
double grey_at(const cv::Mat& g, double x, double y) {
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const double fx = x - x0, fy = y - y0;
  const uchar* r0 = g.ptr<uchar>(y0);
  const uchar* r1 = g.ptr<uchar>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

// A line n.x = c through the edge points of one border edge, n the
// outward unit normal; false when too few points were found.
bool fit_edge(const cv::Mat& g, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& centre,
              double reach, Eigen::Vector2d& n, double& c) {
  const Eigen::Vector2d d = (b - a).normalized();
  n = Eigen::Vector2d(-d.y(), d.x());
  if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
  const double length = (b - a).norm();
  const int samples = std::clamp(int(length), 4, 200);
  const double step = 0.25;
  const int half = int(std::ceil(reach / step));
  std::vector<Eigen::Vector2d> points;
  std::vector<double> profile(std::size_t(2 * half + 1));
  for (int i = 0; i < samples; ++i) {
    // Away from the corners, where the neighbouring edges bend the profile.
    const Eigen::Vector2d q = a + (0.15 + 0.7 * (i + 0.5) / samples) * (b - a);
    bool inside = true;
    for (int j = -half; j <= half && inside; ++j) {
      const Eigen::Vector2d s = q + j * step * n;
      inside = s.x() >= 0 && s.y() >= 0 && s.x() < g.cols - 1 && s.y() < g.rows - 1;
      if (inside) profile[std::size_t(j + half)] = grey_at(g, s.x(), s.y());
    }
    if (!inside) continue;
    const double dark = (profile[0] + profile[1]) / 2,
                 light = (profile[profile.size() - 1] + profile[profile.size() - 2]) / 2;
    if (light - dark < 20) continue;  // too faint to trust
    const double mid = 0.5 * (dark + light);
    // The crossing nearest the middle of the profile.
    double best = 1e9;
    for (int j = 0; j + 1 < int(profile.size()); ++j) {
      const double p0 = profile[std::size_t(j)], p1 = profile[std::size_t(j + 1)];
      if ((p0 - mid) * (p1 - mid) > 0 || p0 == p1) continue;
      const double o = (j - half + (mid - p0) / (p1 - p0)) * step;
      if (std::abs(o) < std::abs(best)) best = o;
    }
    if (best < 1e9) points.push_back(q + best * n);
  }
  if (points.size() < 4) return false;
  // Total least squares: the normal is the covariance's weakest direction.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) mean += p;
  mean /= double(points.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : points) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d fitted = eig.eigenvectors().col(0);
  n = fitted.dot(n) >= 0 ? fitted : Eigen::Vector2d(-fitted);
  c = n.dot(mean);
  return true;
}

}  // namespace

std::array<Eigen::Vector2d, 4> refine_corners(const cv::Mat& grey, const std::array<Eigen::Vector2d, 4>& corners,
                                              int cells) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double perimeter = 0;
  for (std::size_t i = 0; i < 4; ++i)
    centre += 0.25 * corners[i], perimeter += (corners[(i + 1) % 4] - corners[i]).norm();
  // Half a cell of the smallest plausible cell, at most 3 px.
  const double reach = std::min(3.0, 0.5 * perimeter / 4 / cells);
  if (reach < 1) return corners;
  std::array<Eigen::Vector2d, 4> n;
  std::array<double, 4> c{};
  for (std::size_t i = 0; i < 4; ++i)
    if (!fit_edge(grey, corners[i], corners[(i + 1) % 4], centre, reach, n[i], c[i])) return corners;
  // Corner i joins edges i-1 and i.
  std::array<Eigen::Vector2d, 4> out;
  for (std::size_t i = 0; i < 4; ++i) {
    const std::size_t j = (i + 3) % 4;
    Eigen::Matrix2d A;
    A << n[j].transpose(), n[i].transpose();
    if (std::abs(A.determinant()) < 1e-6) return corners;
    out[i] = A.inverse() * (Eigen::Vector2d(c[j], c[i]));
    if ((out[i] - corners[i]).norm() > 2 * reach) return corners;  // a fit gone astray: keep AprilTag's
  }
  return out;
}

Detector::Detector(const DetectorParams& p) : params_((check(p), p)), family_(p.family) {
  detector_ = apriltag_detector_create();
  apriltag_detector_add_family_bits(detector_, family_.get(), p.max_hamming);
  detector_->quad_decimate = float(p.quad_decimate);
  detector_->quad_sigma = float(p.quad_sigma);
  detector_->nthreads = p.nthreads;
  detector_->refine_edges = p.refine_edges;
  detector_->decode_sharpening = p.decode_sharpening;
}

Detector::~Detector() { apriltag_detector_destroy(detector_); }

std::vector<Detection> Detector::detect(const cv::Mat& grey) const {
  if (grey.type() != CV_8UC1 || grey.empty()) throw std::invalid_argument("detector: the frame must be 8-bit grey");
  image_u8_t im{grey.cols, grey.rows, int(grey.step[0]), const_cast<uint8_t*>(grey.ptr())};
  zarray_t* found = apriltag_detector_detect(detector_, &im);
  std::vector<Detection> out;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* d;
    zarray_get(found, i, &d);
    Detection o;
    o.id = d->id, o.hamming = d->hamming, o.decision_margin = d->decision_margin;
    // libapriltag puts pixel centres at +0.5 (its issue #121); OpenCV,
    // and everything here, at integers. Its p[] already runs in our
    // corner order.
    for (int k = 0; k < 4; ++k) o.corners[std::size_t(k)] = {d->p[k][0] - 0.5, d->p[k][1] - 0.5};
    o.centre = {d->c[0] - 0.5, d->c[1] - 0.5};
    if (params_.refine_corners) o.corners = refine_corners(grey, o.corners, family_.border_cells());
    out.push_back(o);
  }
  apriltag_detections_destroy(found);
  return out;
}

}  // namespace hcosim::models::vision
