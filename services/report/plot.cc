#include "services/report/plot.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace hcosim::services::report {
namespace {

// Tableau-like colours (BGR).
const cv::Scalar kPalette[] = {{180, 119, 31},  {14, 127, 255}, {44, 160, 44},   {40, 39, 214},
                               {189, 103, 148}, {75, 86, 140},  {194, 119, 227}, {34, 189, 188}};
const cv::Scalar kInk(40, 40, 40), kGrid(225, 225, 225);
constexpr auto kFont = cv::FONT_HERSHEY_SIMPLEX;

// A step of 1, 2 or 5 times a power of ten giving about `n` ticks over span.
double tick_step(double span, int n) {
  const double raw = span / n, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

std::string tick_label(double v, double step) {
  const int digits = std::max(0, -int(std::floor(std::log10(step) + 1e-9)));
  return cv::format("%.*f", digits, std::abs(v) < 1e-12 * step ? 0.0 : v);
}

}  // namespace

cv::Mat plot_scatter(const std::string& title, const std::string& x_label, const std::string& y_label,
                     const std::vector<Series>& series, Axes axes) {
  const int w = 1100, h = 700, left = 90, right = 300, top = 50, bottom = 70;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  // Positions along each axis: log10 of the value on a log axis.
  const auto fx = [&](double v) { return axes.log_x ? std::log10(v) : v; };
  const auto fy = [&](double v) { return axes.log_y ? std::log10(v) : v; };
  const auto ok = [&](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && (!axes.log_x || x > 0) && (!axes.log_y || y > 0);
  };
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Series& s : series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (ok(s.x[i], s.y[i])) {
        x0 = std::min(x0, fx(s.x[i])), x1 = std::max(x1, fx(s.x[i]));
        y0 = std::min(y0, fy(s.y[i])), y1 = std::max(y1, fy(s.y[i]));
      }
  if (!std::isfinite(x0)) throw std::runtime_error("plot '" + title + "': no point to draw");
  // Whole decades on a log axis; round ticks with zero in view on a linear one.
  struct Ticks {
    double lo, hi, step;
  };
  const auto ticks = [](double lo, double hi, bool log) {
    if (log) return Ticks{std::floor(lo), std::max(std::ceil(hi), std::floor(lo) + 1), 1.0};
    lo = std::min(lo, 0.0), hi = std::max(hi, 0.0);
    if (hi - lo < 1e-12) hi = lo + 1;
    const double step = tick_step(hi - lo, 8);
    return Ticks{std::floor(lo / step) * step, std::ceil(hi / step) * step, step};
  };
  const Ticks tx = ticks(x0, x1, axes.log_x), ty = ticks(y0, y1, axes.log_y);
  // Points on the frame's edge would be cut in half: a margin inside it.
  const int pad = 12;
  const auto px = [&](double v) {
    return left + pad + int((fx(v) - tx.lo) / (tx.hi - tx.lo) * (w - left - right - 2 * pad));
  };
  const auto py = [&](double v) {
    return h - bottom - pad - int((fy(v) - ty.lo) / (ty.hi - ty.lo) * (h - top - bottom - 2 * pad));
  };
  const auto label = [](double t, const Ticks& k, bool log) {
    return log ? "1e" + std::to_string(int(std::lround(t))) : tick_label(t, k.step);
  };
  for (double t = tx.lo; t <= tx.hi + 1e-9 * tx.step; t += tx.step) {
    const int x = px(axes.log_x ? std::pow(10.0, t) : t);
    cv::line(img, {x, top}, {x, h - bottom}, kGrid);
    cv::putText(img, label(t, tx, axes.log_x), {x - 18, h - bottom + 22}, kFont, 0.5, kInk, 1, cv::LINE_AA);
  }
  for (double t = ty.lo; t <= ty.hi + 1e-9 * ty.step; t += ty.step) {
    const int y = py(axes.log_y ? std::pow(10.0, t) : t);
    cv::line(img, {left, y}, {w - right, y}, kGrid);
    cv::putText(img, label(t, ty, axes.log_y), {left - 60, y + 5}, kFont, 0.5, kInk, 1, cv::LINE_AA);
  }
  cv::rectangle(img, {left, top}, {w - right, h - bottom}, kInk);
  cv::putText(img, title, {left, 24}, kFont, 0.65, kInk, 1, cv::LINE_AA);
  cv::putText(img, x_label, {left + (w - left - right) / 2 - 80, h - 20}, kFont, 0.55, kInk, 1, cv::LINE_AA);
  cv::putText(img, y_label, {10, top - 8}, kFont, 0.5, kInk, 1, cv::LINE_AA);
  // Baselines (MuJoCo, bare Fast DDS, OpenCV ArUco) in black and greys;
  // past eight series the colours come round again with another marker.
  int baselines = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const double grey = 110.0 * (baselines % 2);
    const int shape = int(s.baseline ? baselines / 2 : k / 8) % 3;
    const cv::Scalar c = s.baseline ? (++baselines, cv::Scalar(grey, grey, grey)) : kPalette[k % 8];
    const auto mark = [&](cv::Point q) {
      if (shape == 0) cv::circle(img, q, 5, c, cv::FILLED, cv::LINE_AA);
      if (shape == 1) cv::rectangle(img, q - cv::Point(4, 4), q + cv::Point(4, 4), c, cv::FILLED, cv::LINE_AA);
      if (shape == 2) {
        const std::vector<cv::Point> tri = {q + cv::Point(0, -6), q + cv::Point(5, 4), q + cv::Point(-5, 4)};
        cv::fillConvexPoly(img, tri, c, cv::LINE_AA);
      }
    };
    // A thin line through a series' points in x order shows its trend.
    std::vector<cv::Point> points;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (ok(s.x[i], s.y[i])) points.emplace_back(px(s.x[i]), py(s.y[i]));
    std::sort(points.begin(), points.end(), [](const cv::Point& a, const cv::Point& b) { return a.x < b.x; });
    cv::polylines(img, points, false, c, 1, cv::LINE_AA);
    for (const cv::Point& q : points) mark(q);
    const int ly = top + 20 + 24 * int(k);
    mark({w - right + 20, ly - 5});
    cv::putText(img, s.label, {w - right + 32, ly}, kFont, 0.42, kInk, 1, cv::LINE_AA);
  }
  return img;
}

cv::Mat plot_series(const std::string& title, const std::string& x_label, const std::vector<Panel>& panels) {
  if (panels.empty()) throw std::invalid_argument("plot '" + title + "': no panels");
  const int w = 1000, left = 90, right = 200, top = 70, bottom = 60, panel_h = 260, gap = 40;
  const int h = top + bottom + int(panels.size()) * panel_h + int(panels.size() - 1) * gap;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = INFINITY, x1 = -INFINITY;
  for (const Panel& p : panels)
    for (const Series& s : p.series)
      for (double x : s.x)
        if (std::isfinite(x)) x0 = std::min(x0, x), x1 = std::max(x1, x);
  if (!std::isfinite(x0)) x0 = 0, x1 = 1;
  if (x1 <= x0) x1 = x0 + 1;
  const double xs = tick_step(x1 - x0, 10);
  x0 = std::floor(x0 / xs) * xs, x1 = std::ceil(x1 / xs) * xs;
  const auto px = [&](double v) { return left + int(std::lround((v - x0) / (x1 - x0) * (w - left - right))); };
  cv::putText(img, title, {left, 28}, kFont, 0.65, kInk, 1, cv::LINE_AA);
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const Panel& p = panels[k];
    const int y_top = top + int(k) * (panel_h + gap), y_bottom = y_top + panel_h;
    double y0 = INFINITY, y1 = -INFINITY;
    for (const Series& s : p.series)
      for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
        if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
    if (!std::isfinite(y0)) y0 = 0, y1 = 1;
    // Zero stays in view: forces and depths read against it.
    y0 = std::min(y0, 0.0), y1 = std::max(y1, 0.0);
    if (y1 - y0 < 1e-12) y1 = y0 + 1;
    const double ys = tick_step(y1 - y0, 5);
    y0 = std::floor(y0 / ys) * ys, y1 = std::ceil(y1 / ys) * ys;
    const auto py = [&](double v) { return y_bottom - int(std::lround((v - y0) / (y1 - y0) * panel_h)); };
    for (double v = x0; v <= x1 + 1e-9 * xs; v += xs) {
      cv::line(img, {px(v), y_top}, {px(v), y_bottom}, kGrid);
      if (k + 1 == panels.size())
        cv::putText(img, tick_label(v, xs), {px(v) - 12, y_bottom + 20}, kFont, 0.45, kInk, 1, cv::LINE_AA);
    }
    for (double v = y0; v <= y1 + 1e-9 * ys; v += ys) {
      cv::line(img, {left, py(v)}, {w - right, py(v)}, kGrid);
      cv::putText(img, tick_label(v, ys), {left - 60, py(v) + 5}, kFont, 0.45, kInk, 1, cv::LINE_AA);
    }
    cv::rectangle(img, {left, y_top}, {w - right, y_bottom}, kInk);
    cv::putText(img, p.y_label, {left, y_top - 8}, kFont, 0.5, kInk, 1, cv::LINE_AA);
    for (std::size_t j = 0; j < p.series.size(); ++j) {
      const Series& s = p.series[j];
      const cv::Scalar c = kPalette[j % 8];
      std::vector<cv::Point> line;
      const auto flush = [&] {
        if (line.size() > 1) cv::polylines(img, line, false, c, 2, cv::LINE_AA);
        if (line.size() == 1) cv::circle(img, line[0], 2, c, cv::FILLED, cv::LINE_AA);
        line.clear();
      };
      for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
          line.emplace_back(px(s.x[i]), py(s.y[i]));
        else
          flush();
      }
      flush();
      const int ly = y_top + 20 + 22 * int(j);
      cv::line(img, {w - right + 15, ly - 5}, {w - right + 35, ly - 5}, c, 2, cv::LINE_AA);
      cv::putText(img, s.label, {w - right + 42, ly}, kFont, 0.45, kInk, 1, cv::LINE_AA);
    }
  }
  cv::putText(img, x_label, {left + (w - left - right) / 2 - 40, h - 15}, kFont, 0.55, kInk, 1, cv::LINE_AA);
  return img;
}

}  // namespace hcosim::services::report
