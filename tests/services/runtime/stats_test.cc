#include <cmath>

#include <gtest/gtest.h>

#include "services/runtime/stats.h"

namespace hcosim::services::runtime {
namespace {

TEST(Window, NearestRankPercentiles) {
  Window w(1000);
  for (int i = 100; i >= 1; --i) w.add(i);
  EXPECT_EQ(w.percentile(0.5), 50);
  EXPECT_EQ(w.percentile(0.99), 99);
  EXPECT_EQ(w.percentile(1.0), 100);
  EXPECT_EQ(w.percentile(0.0), 1);
  EXPECT_EQ(w.count_at_most(37), 37u);
  EXPECT_EQ(w.count_at_most(0.5), 0u);
}

TEST(Window, KeepsOnlyTheLatestValues) {
  Window w(4);
  for (int i = 1; i <= 10; ++i) w.add(i);
  EXPECT_EQ(w.size(), 4u);
  EXPECT_EQ(w.percentile(0.0), 7);
  EXPECT_EQ(w.percentile(1.0), 10);
  EXPECT_EQ(w.count_at_most(8), 2u);
}

TEST(Window, EmptyAndClearedAreNaN) {
  Window w(4);
  EXPECT_TRUE(std::isnan(w.percentile(0.5)));
  w.add(3);
  w.clear();
  EXPECT_TRUE(std::isnan(w.percentile(0.5)));
  EXPECT_THROW(Window(0), std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::services::runtime
