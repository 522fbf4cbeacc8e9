// Log-log scatter plots for bench reports, drawn with OpenCV.
#pragma once

#include <string>
#include <vector>

namespace hcosim::cli {

struct Series {
  std::string label;
  std::vector<double> x, y;  // > 0; non-positive or non-finite points are skipped
};

// Writes a PNG at `path` with both axes logarithmic and one colour per series.
void plot_loglog(const std::string& path, const std::string& title, const std::string& x_label,
                 const std::string& y_label, const std::vector<Series>& series);

}  // namespace hcosim::cli
