// JSON as the adapters write it: nesting, escapes, null for non-finite
// numbers, doubles that read back exactly.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "adapters/json.h"

namespace hcosim::adapters {
namespace {

TEST(Json, NestsAndSeparates) {
  Json j;
  j.begin_object().key("a").value(1).key("b").begin_array().value(true).value("x").end_array();
  j.key("c").begin_object().end_object().end_object();
  EXPECT_EQ(j.str(), R"({"a":1,"b":[true,"x"],"c":{}})");
}

TEST(Json, EscapesStrings) {
  Json j;
  j.value("quote\" back\\ nl\n tab\t bell\a");
  EXPECT_EQ(j.str(), R"("quote\" back\\ nl\n tab\t bell\u0007")");
}

TEST(Json, NonFiniteBecomesNull) {
  Json j;
  j.begin_array().value(std::nan("")).value(std::numeric_limits<double>::infinity()).value(0.5).end_array();
  EXPECT_EQ(j.str(), "[null,null,0.5]");
}

TEST(Json, DoublesRoundTrip) {
  const double v = 0.1 + 0.2;
  Json j;
  j.value(v);
  EXPECT_EQ(std::stod(j.str()), v);
}

}  // namespace
}  // namespace hcosim::adapters
