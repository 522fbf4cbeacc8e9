#include "render/view.h"

#include <opencv2/imgproc.hpp>

namespace hcosim::render {
namespace {

constexpr double kLeastForce = 0.01;  // N: smaller forces draw no arrow
const cv::Scalar kStylus(70, 70, 70), kTip(40, 200, 255), kArrow(30, 30, 230);

}  // namespace

cv::Scalar object_colour(std::size_t i) {
  const cv::Scalar palette[] = {{200, 140, 60}, {60, 170, 90}, {70, 110, 220}, {170, 80, 170},
                                {40, 170, 200}, {150, 150, 40}, {110, 90, 200}, {90, 200, 160}};
  return palette[i % 8];
}

void draw(const View& v, Canvas& c) {
  for (const Object& o : v.objects) c.mesh(o.mesh.vertices, o.mesh.triangles, o.colour);
  if (!v.stylus) return;
  const Stylus& s = *v.stylus;
  Eigen::Isometry3d pen = Eigen::Isometry3d::Identity();
  pen.linear() = s.orientation;
  pen.translation() = s.tip;
  const Mesh body = placed(cylinder(v.stylus_radius, v.stylus_length), pen);
  c.mesh(body.vertices, body.triangles, kStylus);
  const Mesh tip = placed(sphere(1.5 * v.stylus_radius, 6), pen);
  c.mesh(tip.vertices, tip.triangles, kTip);
  if (s.force.norm() < kLeastForce) return;
  double d0 = 0, d1 = 0;
  const Eigen::Vector2d a = c.project(s.tip, &d0), b = c.project(s.tip + v.force_scale * s.force, &d1);
  if (d0 <= 0 || d1 <= 0) return;
  cv::Mat img = c.image();
  cv::arrowedLine(img, {int(std::lround(a.x())), int(std::lround(a.y()))}, {int(std::lround(b.x())), int(std::lround(b.y()))},
                  kArrow, 3, cv::LINE_AA, 0, 0.25);
}

}  // namespace hcosim::render
