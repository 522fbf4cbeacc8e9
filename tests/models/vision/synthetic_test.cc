// The synthetic camera draws the sheet whole and nothing else; random
// poses keep their ranges and seed.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "models/vision/detector.h"
#include "models/vision/pose.h"
#include "models/vision/synthetic.h"
#include "tests/support/tag_views.h"

namespace hcosim::models::vision {
namespace {

using tests::kDeg;
using tests::tilted;

// The render warps only the sheet's footprint: over poses near and far,
// some with the sheet past the frame's edge, every pixel 1.5 px outside the
// sheet's outline is one background grey and every one 1.5 px inside it, off
// the tag, is the sheet's white (nothing of the sheet is cut off).
TEST(Vision, TheSheetIsDrawnWholeAndNothingElse) {
  const Intrinsics k = synthetic_intrinsics(640, 480);
  const Marker m;  // a sheet of 2 tag sizes: its edge at +-tag_size
  const SyntheticCamera cam(k, m);
  const auto outline = [&](const Eigen::Isometry3d& pose, double half) {
    std::vector<cv::Point2f> q;
    for (const Eigen::Vector3d& c : {Eigen::Vector3d(-half, -half, 0), Eigen::Vector3d(half, -half, 0),
                                     Eigen::Vector3d(half, half, 0), Eigen::Vector3d(-half, half, 0)}) {
      const Eigen::Vector2d p = project(k, pose, c);
      q.emplace_back(float(p.x()), float(p.y()));
    }
    return q;
  };
  // The tag's own white margin reaches 10/8 of its black border.
  const double sheet = m.tag_size, margin = 0.5 * m.tag_size * 10 / 8;
  std::vector<Eigen::Isometry3d> poses = random_poses(k, m.tag_size, 12, 5, 0.12, 0.9);
  poses.push_back(tilted(0.1, 0, 0, 0.03));  // the sheet past the left edge
  for (const Eigen::Isometry3d& pose : poses) {
    const cv::Mat f = cam.render(pose);
    const std::vector<cv::Point2f> s = outline(pose, sheet), t = outline(pose, margin);
    int outside = 0, inside = 0, background = -1;
    for (int y = 0; y < f.rows; ++y)
      for (int x = 0; x < f.cols; ++x) {
        const cv::Point2f px{float(x), float(y)};
        const double ds = cv::pointPolygonTest(s, px, true), dt = cv::pointPolygonTest(t, px, true);
        if (ds < -1.5) {
          ++outside;
          if (background < 0) background = f.at<std::uint8_t>(y, x);
          ASSERT_EQ(f.at<std::uint8_t>(y, x), background) << "pixel " << x << "," << y << " outside the sheet";
        } else if (ds > 1.5 && dt < -1.5) {
          ++inside;
          ASSERT_GE(f.at<std::uint8_t>(y, x), 200) << "pixel " << x << "," << y << " on the sheet";
        }
      }
    EXPECT_GT(outside, 0);
    EXPECT_LT(background, 200);
    EXPECT_GT(inside, 100);
  }
}

TEST(Vision, RandomPosesKeepTheirRangesAndSeed) {
  const Intrinsics k = synthetic_intrinsics(640, 480);
  const auto a = random_poses(k, 0.05, 50, 11), b = random_poses(k, 0.05, 50, 11);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a[i].isApprox(b[i], 0));
    const double d = a[i].translation().norm(), tilt = std::acos(-a[i].linear()(2, 2)) / kDeg;
    EXPECT_GE(d, 0.15);
    EXPECT_LE(d, 0.7);
    EXPECT_LE(tilt, 55 + 1e-9);
  }
}

}  // namespace
}  // namespace hcosim::models::vision
