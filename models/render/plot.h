// Plots as PNG, drawn with OpenCV: log-log scatter plots for bench
// reports, and time series for run reports.
#pragma once

#include <string>
#include <vector>

namespace hcosim::render {

struct Series {
  std::string label;
  std::vector<double> x, y;  // plot_loglog skips non-positive and non-finite points
};

// Writes a PNG at `path` with both axes logarithmic and one colour per series.
void plot_loglog(const std::string& path, const std::string& title, const std::string& x_label,
                 const std::string& y_label, const std::vector<Series>& series);

// Panels stacked over one shared x axis, linear scales, one line per series.
struct Panel {
  std::string y_label;          // with its unit, e.g. "force (N)"
  std::vector<Series> series;   // non-finite points are skipped
};

// Writes a PNG at `path`. Throws std::runtime_error when the file cannot be
// written, std::invalid_argument when there are no panels.
void plot_series(const std::string& path, const std::string& title, const std::string& x_label,
                 const std::vector<Panel>& panels);

}  // namespace hcosim::render
