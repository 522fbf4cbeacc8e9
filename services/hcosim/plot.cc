#include "plot.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace hcosim::cli {

void plot_loglog(const std::string& path, const std::string& title, const std::string& x_label,
                 const std::string& y_label, const std::vector<Series>& series) {
  const int w = 1000, h = 700, left = 90, right = 220, top = 50, bottom = 70;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  auto ok = [](double v) { return std::isfinite(v) && v > 0; };
  for (const Series& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (ok(s.x[i]) && ok(s.y[i])) {
        x0 = std::min(x0, std::log10(s.x[i])), x1 = std::max(x1, std::log10(s.x[i]));
        y0 = std::min(y0, std::log10(s.y[i])), y1 = std::max(y1, std::log10(s.y[i]));
      }
  if (!std::isfinite(x0)) throw std::runtime_error("plot " + path + ": no positive points");
  // Whole decades around the data.
  x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1), y0 = std::floor(y0), y1 = std::max(std::ceil(y1), y0 + 1);
  auto px = [&](double v) { return left + int((std::log10(v) - x0) / (x1 - x0) * (w - left - right)); };
  auto py = [&](double v) { return h - bottom - int((std::log10(v) - y0) / (y1 - y0) * (h - top - bottom)); };
  const cv::Scalar ink(40, 40, 40), grid(225, 225, 225);
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (int d = int(x0); d <= int(x1); ++d) {
    const int x = px(std::pow(10.0, d));
    cv::line(img, {x, top}, {x, h - bottom}, grid);
    cv::putText(img, "1e" + std::to_string(d), {x - 18, h - bottom + 22}, font, 0.5, ink, 1, cv::LINE_AA);
  }
  for (int d = int(y0); d <= int(y1); ++d) {
    const int y = py(std::pow(10.0, d));
    cv::line(img, {left, y}, {w - right, y}, grid);
    cv::putText(img, "1e" + std::to_string(d), {left - 50, y + 5}, font, 0.5, ink, 1, cv::LINE_AA);
  }
  cv::rectangle(img, {left, top}, {w - right, h - bottom}, ink);
  cv::putText(img, title, {left, 24}, font, 0.65, ink, 1, cv::LINE_AA);
  cv::putText(img, x_label, {left + (w - left - right) / 2 - 80, h - 20}, font, 0.55, ink, 1, cv::LINE_AA);
  cv::putText(img, y_label, {10, top - 8}, font, 0.5, ink, 1, cv::LINE_AA);
  // Tableau-like colours (BGR); MuJoCo, the baseline, in black and greys.
  const cv::Scalar palette[] = {{180, 119, 31}, {14, 127, 255}, {44, 160, 44}, {40, 39, 214},
                                {189, 103, 148}, {75, 86, 140}, {194, 119, 227}, {34, 189, 188}};
  int baselines = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const double grey = 110.0 * baselines;
    const cv::Scalar c = s.label.rfind("mujoco", 0) == 0 ? (++baselines, cv::Scalar(grey, grey, grey)) : palette[k % 8];
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (ok(s.x[i]) && ok(s.y[i])) cv::circle(img, {px(s.x[i]), py(s.y[i])}, 5, c, cv::FILLED, cv::LINE_AA);
    const int ly = top + 20 + 24 * int(k);
    cv::circle(img, {w - right + 20, ly - 5}, 5, c, cv::FILLED, cv::LINE_AA);
    cv::putText(img, s.label, {w - right + 32, ly}, font, 0.45, ink, 1, cv::LINE_AA);
  }
  if (!cv::imwrite(path, img)) throw std::runtime_error("plot: cannot write " + path);
}

}  // namespace hcosim::cli
