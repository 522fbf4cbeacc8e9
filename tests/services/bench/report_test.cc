// The report's part of docs/PERFORMANCE.md: every goal of every suite with
// its verdict and worst figure, judged from the rows, and the tree that
// measured them.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "services/bench/bench.h"

namespace hcosim::services::bench {
namespace {

Suite suite() {
  Suite s{"demo", "a suite of two rows", nullptr};
  s.goals = {{"p99 within 100 us", "tick", "p99_us", 100},
             {"at least 10 times faster", "tick", "speedup", 10, "", "", true},
             {"nothing lost, fast ones", "tick", "lost", 0, "kind", "fast"},
             {"a row no run had", "other", "x", 1}};
  return s;
}

TEST(Report, ThePagePartJudgesEveryGoalFromTheRows) {
  const Suite s = suite();
  Result r{&s, {}, {}, "hcosim bench demo --out x", {}, Provenance{"0123456789abcdef", true}, 1.0, ""};
  r.rows = {{"tick", {{"kind", std::string("fast")}}, {{"p99_us", 40}, {"speedup", 12}, {"lost", 0}}},
            {"tick", {{"kind", std::string("slow")}}, {{"p99_us", 140}, {"speedup", 30}, {"lost", 3}}}};
  const std::string part = page_part({r});
  EXPECT_NE(part.find("Measured by `hcosim bench demo --out x` at commit `0123456789abcdef` (a clean tree)"),
            std::string::npos)
      << part;
  EXPECT_NE(part.find("| `demo` | p99 within 100 us | `tick`: `p99_us` <= 100 | 140 (2 rows) | **not met** |"),
            std::string::npos)
      << part;
  EXPECT_NE(part.find("| `demo` | at least 10 times faster | `tick`: `speedup` >= 10 | 12 (2 rows) | met |"),
            std::string::npos)
      << part;
  EXPECT_NE(part.find("| `tick` with kind fast: `lost` <= 0 | 0 (1 row) | met |"), std::string::npos) << part;
  EXPECT_NE(part.find("| `other`: `x` <= 1 |  | not measured |"), std::string::npos) << part;

  r.tree.clean = false;
  EXPECT_NE(page_part({r}).find("(**with changes git had not committed**)"), std::string::npos);
  r.error = "it crashed";
  EXPECT_NE(page_part({r}).find("| the suite failed |"), std::string::npos);
}

}  // namespace
}  // namespace hcosim::services::bench
