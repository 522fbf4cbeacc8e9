// Percentiles of durations over a reporting period.
#pragma once

#include <cstddef>
#include <vector>

namespace hcosim::services::runtime {

// Keeps the latest `capacity` values (a ring) and answers percentiles of
// them. Sized for one heartbeat period of a 1 kHz loop.
class Window {
 public:
  explicit Window(std::size_t capacity = 8192);
  void add(double value);
  // q in [0, 1]; NaN when empty.
  double percentile(double q) const;
  // How many of the values are <= v.
  std::size_t count_at_most(double v) const;
  std::size_t size() const { return full_ ? values_.size() : next_; }
  void clear();

 private:
  std::vector<double> values_;
  std::size_t next_ = 0;
  bool full_ = false;
  mutable std::vector<double> scratch_;
};

}  // namespace hcosim::services::runtime
