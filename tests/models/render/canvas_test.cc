// The renderer puts objects where the camera sees them: a square on the
// marker covers exactly the pixels inside its projected corners, the
// nearer of two overlapping squares shows whatever the drawing order, a
// tilted face is darker than a facing one, and bad input is refused.
#include <gtest/gtest.h>

#include "models/render/canvas.h"
#include "models/vision/synthetic.h"

namespace hcosim::models::render {
namespace {

// A square of edge `size` (m) at height z on the marker, centred at (cx, cy).
void square(Canvas& canvas, double size, double z, const cv::Scalar& colour, double cx = 0, double cy = 0) {
  const double h = size / 2;
  Eigen::Matrix3Xd v(3, 4);
  v << cx - h, cx + h, cx + h, cx - h, cy - h, cy - h, cy + h, cy + h, z, z, z, z;
  canvas.mesh(v, {0, 1, 2, 0, 2, 3}, colour);
}

cv::Vec3b at(const Canvas& c, const Eigen::Vector2d& p) {
  return c.image().at<cv::Vec3b>(int(std::lround(p.y())), int(std::lround(p.x())));
}

TEST(Render, SquareOnTheMarkerCoversItsProjectedCorners) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  const Eigen::Isometry3d view = models::vision::facing(0.35);
  Canvas canvas(cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0)), k, view);
  square(canvas, 0.04, 0, cv::Scalar(0, 0, 200));
  // 4 cm at 0.35 m and f = 600 px: 68.6 px a side, centred on the image.
  const Eigen::Vector2d lo = canvas.project({-0.02, 0.02, 0}), hi = canvas.project({0.02, -0.02, 0});
  EXPECT_NEAR(hi.x() - lo.x(), 600 * 0.04 / 0.35, 1e-9);
  EXPECT_EQ(at(canvas, canvas.project({0, 0, 0})), cv::Vec3b(0, 0, 200));  // facing: full colour
  for (const auto& [dx, dy] :
       {std::pair{1.5, 1.5}, std::pair{-1.5, 1.5}, std::pair{1.5, -1.5}, std::pair{-1.5, -1.5}}) {
    // 1.5 px inside each edge is drawn, 1.5 px outside is not.
    const Eigen::Vector2d inside(dx > 0 ? lo.x() + dx : hi.x() + dx, dy > 0 ? lo.y() + dy : hi.y() + dy);
    const Eigen::Vector2d outside(dx > 0 ? lo.x() - dx : hi.x() - dx, dy > 0 ? lo.y() - dy : hi.y() - dy);
    EXPECT_EQ(at(canvas, inside)[2], 200) << inside.transpose();
    EXPECT_EQ(at(canvas, outside)[2], 0) << outside.transpose();
  }
  const double side = 600 * 0.04 / 0.35;
  EXPECT_NEAR(double(canvas.pixels()), side * side, 4 * side);
}

TEST(Render, TheNearerSurfaceShowsWhateverTheOrder) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  for (const bool near_first : {false, true}) {
    Canvas canvas(cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0)), k, models::vision::facing(0.35));
    // z points out of the marker toward the camera: z = 0.01 is nearer.
    if (near_first) square(canvas, 0.02, 0.01, cv::Scalar(255, 0, 0));
    square(canvas, 0.04, 0, cv::Scalar(0, 0, 255));
    if (!near_first) square(canvas, 0.02, 0.01, cv::Scalar(255, 0, 0));
    EXPECT_EQ(at(canvas, canvas.project({0, 0, 0.01})), cv::Vec3b(255, 0, 0)) << near_first;
    EXPECT_EQ(at(canvas, canvas.project({0.017, 0, 0})), cv::Vec3b(0, 0, 255)) << near_first;
  }
}

TEST(Render, TiltedFacesAreDarker) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  Eigen::Isometry3d tilted = models::vision::facing(0.35);
  tilted.linear() = tilted.linear() * Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  Canvas facing(cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0)), k, models::vision::facing(0.35));
  Canvas turned(cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0)), k, tilted);
  square(facing, 0.04, 0, cv::Scalar(0, 200, 0));
  square(turned, 0.04, 0, cv::Scalar(0, 200, 0));
  const int bright = at(facing, facing.project({0, 0, 0}))[1], dim = at(turned, turned.project({0, 0, 0}))[1];
  EXPECT_EQ(bright, 200);
  EXPECT_LT(dim, 170);
  EXPECT_GT(dim, 0);
}

TEST(Render, BadInputIsRefused) {
  const models::vision::Intrinsics k = models::vision::synthetic_intrinsics(640, 480);
  EXPECT_THROW(Canvas(cv::Mat(480, 640, CV_8UC1), k, models::vision::facing(0.35)), std::invalid_argument);
  EXPECT_THROW(Canvas(cv::Mat(240, 320, CV_8UC3), k, models::vision::facing(0.35)), std::invalid_argument);
  Canvas canvas(cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0)), k, models::vision::facing(0.35));
  EXPECT_THROW(canvas.mesh(Eigen::Matrix3Xd::Zero(3, 3), {0, 1, 3}, cv::Scalar(1, 1, 1)), std::invalid_argument);
  EXPECT_THROW(canvas.mesh(Eigen::Matrix3Xd::Zero(3, 3), {0, 1}, cv::Scalar(1, 1, 1)), std::invalid_argument);
  // Behind the camera: nothing drawn, nothing thrown.
  Eigen::Matrix3Xd behind(3, 3);
  behind << 0, 0.01, 0, 0, 0, 0.01, 0.5, 0.5, 0.5;
  canvas.mesh(behind, {0, 1, 2}, cv::Scalar(1, 1, 1));
  EXPECT_EQ(canvas.pixels(), 0u);
}

}  // namespace
}  // namespace hcosim::models::render
