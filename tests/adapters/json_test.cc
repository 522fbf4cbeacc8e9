// JSON as the adapters write and read it: keys in the order written, null
// for non-finite numbers, doubles that read back exactly, floats written
// as their shortest text, and a located error for text that is not JSON.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "adapters/config.h"
#include "adapters/json.h"

namespace hcosim::adapters {
namespace {

TEST(Json, KeepsTheOrderKeysWereWrittenIn) {
  Json j;
  j["b"] = 1;
  j["a"] = {true, "x"};
  j["c"] = Json::object();
  EXPECT_EQ(json_line(j), R"({"b":1,"a":[true,"x"],"c":{}})");
}

TEST(Json, EscapesStringsAndReplacesBadUtf8) {
  EXPECT_EQ(json_line(Json("quote\" back\\ nl\n tab\t bell\a")), R"("quote\" back\\ nl\n tab\t bell\u0007")");
  EXPECT_EQ(json_line(Json("bad \xff byte")), "\"bad \xEF\xBF\xBD byte\"");
}

TEST(Json, NonFiniteBecomesNull) {
  const Json j = {std::nan(""), std::numeric_limits<double>::infinity(), 0.5};
  EXPECT_EQ(json_line(j), "[null,null,0.5]");
}

TEST(Json, DoublesRoundTripAndFloatsKeepTheirShortestText) {
  const double v = 0.1 + 0.2;
  EXPECT_EQ(parse_json(json_line(Json(v)), "test").get<double>(), v);
  EXPECT_EQ(json_line(Json(json_float(0.1f))), "0.1");
  EXPECT_EQ(float(json_float(0.1f)), 0.1f);
  EXPECT_EQ(float(json_float(3.4028235e38f)), 3.4028235e38f);
  EXPECT_TRUE(std::isnan(json_float(std::nanf(""))));
}

TEST(Json, TextThatIsNotJsonIsALocatedError) {
  try {
    parse_json(R"({"frame": 1,)", "poses.jsonl:3");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("poses.jsonl:3: not JSON:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hcosim::adapters
