#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "adapters/idl_json.h"
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

TEST(IdlJson, HapticStateHasEveryField) {
  HapticState s;
  s.device("omni");
  s.seq(42);
  s.position().z(-0.25);
  s.orientation().w(1.0);
  const std::string j = to_json(s);
  EXPECT_NE(j.find(R"("device":"omni")"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("seq":42)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("position":{"x":0,"y":0,"z":-0.25})"), std::string::npos) << j;
  for (const char* k : {"stamp", "velocity", "orientation", "buttons", "rendered_force", "device_time_s"})
    EXPECT_NE(j.find(std::string("\"") + k + "\""), std::string::npos) << k;
}

TEST(IdlJson, CameraFrameSummarisesPixels) {
  CameraFrame f;
  f.data().assign(640 * 480 * 3, 7);
  const std::string j = to_json(f);
  EXPECT_NE(j.find(R"("data_bytes":921600)"), std::string::npos);
  EXPECT_LT(j.size(), 1000u);
}

}  // namespace
}  // namespace hcosim::adapters
