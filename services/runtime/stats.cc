#include "services/runtime/stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hcosim::services::runtime {

Window::Window(std::size_t capacity) : values_(capacity) {
  if (capacity == 0) throw std::invalid_argument("Window capacity must be positive");
  scratch_.reserve(capacity);
}

void Window::add(double value) {
  values_[next_] = value;
  if (++next_ == values_.size()) {
    next_ = 0;
    full_ = true;
  }
}

double Window::percentile(double q) const {
  const std::size_t n = size();
  if (n == 0) return std::nan("");
  scratch_.assign(values_.begin(), values_.begin() + n);
  // Nearest-rank percentile: the smallest value with at least q of the data at or below it.
  const std::size_t rank = q <= 0 ? 0 : std::min(n - 1, static_cast<std::size_t>(std::ceil(q * n)) - 1);
  std::nth_element(scratch_.begin(), scratch_.begin() + rank, scratch_.end());
  return scratch_[rank];
}

std::size_t Window::count_at_most(double v) const {
  return std::size_t(std::count_if(values_.begin(), values_.begin() + size(), [v](double x) { return x <= v; }));
}

void Window::clear() {
  next_ = 0;
  full_ = false;
}

}  // namespace hcosim::services::runtime
