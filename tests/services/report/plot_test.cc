// Plots as images: stacked time panels are drawn with each series' colour.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "services/report/plot.h"

namespace hcosim::services::report {

namespace {

TEST(ArPlot, DrawsStackedTimePanels) {
  Series a{"cube", {0, 1, 2, 3}, {0, 0.5, 1.0, 0.2}}, b{"organ", {0, 1, NAN, 3}, {0, 2, 1, 0}};
  const cv::Mat img = plot_series("forces", "simulated time (s)", {{"force (N)", {a, b}}, {"penetration (mm)", {a}}});
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 1000);
  EXPECT_GT(img.rows, 500);
  // The first series' colour (BGR 180, 119, 31) is drawn.
  cv::Mat mask;
  cv::inRange(img, cv::Scalar(170, 110, 20), cv::Scalar(190, 130, 45), mask);
  EXPECT_GT(cv::countNonZero(mask), 100);
  EXPECT_THROW(plot_series("none", "x", {}), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::services::report
