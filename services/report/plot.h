// Plots drawn with OpenCV, as BGR images (written as PNG by their callers):
// scatter plots for bench reports, and time series for run reports.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace hcosim::services::report {

struct Series {
  std::string label;
  std::vector<double> x, y;  // non-finite points are skipped, and non-positive ones on a log axis
  bool baseline = false;     // a peer measured for comparison: drawn in grey
};

// Each axis of a scatter plot: logarithmic (whole decades) or linear (with zero in view).
struct Axes {
  bool log_x = true, log_y = true;
};

// One colour per series. Throws std::runtime_error when no point can be drawn.
cv::Mat plot_scatter(const std::string& title, const std::string& x_label, const std::string& y_label,
                     const std::vector<Series>& series, Axes axes = {});

// Panels stacked over one shared x axis, linear scales, one line per series.
struct Panel {
  std::string y_label;         // with its unit, e.g. "force (N)"
  std::vector<Series> series;  // non-finite points are skipped
};

// Throws std::invalid_argument when there are no panels.
cv::Mat plot_series(const std::string& title, const std::string& x_label, const std::vector<Panel>& panels);

}  // namespace hcosim::services::report
