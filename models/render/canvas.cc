#include "models/render/canvas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace hcosim::models::render {
namespace {

constexpr double kNear = 0.01;     // m: closer triangles are skipped, not clipped
constexpr double kAmbient = 0.35;  // shade of a triangle seen edge-on

}  // namespace

Canvas::Canvas(cv::Mat bgr, const models::vision::Intrinsics& k, const Eigen::Isometry3d& world_in_camera)
    : bgr_(bgr), k_(k), world_in_camera_(world_in_camera) {
  models::vision::check(k);
  if (bgr.type() != CV_8UC3 || bgr.cols != k.width || bgr.rows != k.height)
    throw std::invalid_argument("canvas: the image must be 8-bit BGR of the intrinsics' size " +
                                std::to_string(k.width) + "x" + std::to_string(k.height));
  depth_ = cv::Mat(bgr.rows, bgr.cols, CV_32F, cv::Scalar(std::numeric_limits<float>::infinity()));
}

void Canvas::arrow(const Eigen::Vector3d& from, const Eigen::Vector3d& to, const cv::Scalar& colour, int thickness) {
  double d0 = 0, d1 = 0;
  const Eigen::Vector2d a = project(from, &d0), b = project(to, &d1);
  if (d0 < kNear || d1 < kNear) return;
  cv::arrowedLine(bgr_, {int(std::lround(a.x())), int(std::lround(a.y()))},
                  {int(std::lround(b.x())), int(std::lround(b.y()))}, colour, thickness, cv::LINE_AA, 0, 0.25);
}

Eigen::Vector2d Canvas::project(const Eigen::Vector3d& world, double* depth) const {
  const Eigen::Vector3d c = world_in_camera_ * world;
  if (depth) *depth = c.z();
  std::vector<cv::Point3d> in{{c.x(), c.y(), c.z()}};
  std::vector<cv::Point2d> out;
  cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), models::vision::camera_matrix(k_),
                    models::vision::distortion(k_), out);
  return {out[0].x, out[0].y};
}

void Canvas::mesh(const Eigen::Matrix3Xd& vertices, const std::vector<std::uint32_t>& triangles,
                  const cv::Scalar& colour) {
  if (triangles.size() % 3) throw std::invalid_argument("canvas: triangles must come in threes of indices");
  for (const std::uint32_t i : triangles)
    if (i >= vertices.cols())
      throw std::invalid_argument("canvas: triangle index " + std::to_string(i) + " out of range");
  if (vertices.cols() == 0) return;
  // Every vertex in the camera frame and in the image (with distortion).
  const Eigen::Matrix3Xd cam = world_in_camera_ * vertices;
  std::vector<cv::Point3d> in(std::size_t(cam.cols()));
  for (Eigen::Index v = 0; v < cam.cols(); ++v) in[std::size_t(v)] = {cam(0, v), cam(1, v), std::max(cam(2, v), kNear)};
  std::vector<cv::Point2d> px;
  cv::projectPoints(in, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), models::vision::camera_matrix(k_),
                    models::vision::distortion(k_), px);

  for (std::size_t t = 0; t < triangles.size(); t += 3) {
    const std::uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    const Eigen::Vector3d pa = cam.col(a), pb = cam.col(b), pc = cam.col(c);
    if (pa.z() < kNear || pb.z() < kNear || pc.z() < kNear) continue;
    // Lambert with the light at the camera, both sides lit.
    const Eigen::Vector3d n = (pb - pa).cross(pc - pa);
    const Eigen::Vector3d centre = (pa + pb + pc) / 3;
    if (n.norm() < 1e-15) continue;
    const double facing = std::abs(n.normalized().dot(centre.normalized()));
    const double shade = kAmbient + (1 - kAmbient) * facing;
    const cv::Vec3b fill(cv::saturate_cast<std::uint8_t>(colour[0] * shade),
                         cv::saturate_cast<std::uint8_t>(colour[1] * shade),
                         cv::saturate_cast<std::uint8_t>(colour[2] * shade));
    const cv::Point2d &A = px[a], &B = px[b], &C = px[c];
    const double area = (B.x - A.x) * (C.y - A.y) - (B.y - A.y) * (C.x - A.x);
    if (std::abs(area) < 1e-12) continue;
    // Pixel centres inside the triangle, with 1/z interpolated linearly in
    // the image (perspective-correct depth).
    const int x0 = std::max(0, int(std::ceil(std::min({A.x, B.x, C.x}))));
    const int x1 = std::min(bgr_.cols - 1, int(std::floor(std::max({A.x, B.x, C.x}))));
    const int y0 = std::max(0, int(std::ceil(std::min({A.y, B.y, C.y}))));
    const int y1 = std::min(bgr_.rows - 1, int(std::floor(std::max({A.y, B.y, C.y}))));
    const double iza = 1 / pa.z(), izb = 1 / pb.z(), izc = 1 / pc.z();
    for (int y = y0; y <= y1; ++y) {
      float* depth = depth_.ptr<float>(y);
      cv::Vec3b* row = bgr_.ptr<cv::Vec3b>(y);
      for (int x = x0; x <= x1; ++x) {
        // Barycentric weights of the pixel centre (x, y).
        const double wa = ((B.x - x) * (C.y - y) - (B.y - y) * (C.x - x)) / area;
        const double wb = ((C.x - x) * (A.y - y) - (C.y - y) * (A.x - x)) / area;
        const double wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const float z = float(1 / (wa * iza + wb * izb + wc * izc));
        if (z >= depth[x]) continue;
        depth[x] = z;
        row[x] = fill;
        ++pixels_;
      }
    }
  }
}

}  // namespace hcosim::models::render
