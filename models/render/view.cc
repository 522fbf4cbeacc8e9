#include "models/render/view.h"

namespace hcosim::models::render {
namespace {

constexpr double kLeastForce = 0.01;  // N: smaller forces draw no arrow
const cv::Scalar kStylus(70, 70, 70), kTip(40, 200, 255), kArrow(30, 30, 230);

}  // namespace

cv::Scalar object_colour(std::size_t i) {
  const cv::Scalar palette[] = {{200, 140, 60}, {60, 170, 90},  {70, 110, 220}, {170, 80, 170},
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
  if (s.force.norm() >= kLeastForce) c.arrow(s.tip, s.tip + v.force_scale * s.force, kArrow, 3);
}

}  // namespace hcosim::models::render
