// Samples as JSON lines (hcosim echo, export): every field of a
// HapticState, fields in the IDL's order, mesh floats as their shortest
// text, a CameraFrame's pixels summarised.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "adapters/idl_json.h"

namespace hcosim::adapters {
namespace {

TEST(IdlJson, HapticStateHasEveryField) {
  HapticState s;
  s.device("omni");
  s.seq(42);
  s.position().z(-0.25);
  s.orientation().w(1.0);
  const std::string j = to_json(s);
  EXPECT_NE(j.find(R"("device":"omni")"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("seq":42)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("position":{"x":0.0,"y":0.0,"z":-0.25})"), std::string::npos) << j;
  for (const char* k : {"stamp", "velocity", "orientation", "buttons", "rendered_force", "device_time_s"})
    EXPECT_NE(j.find(std::string("\"") + k + "\""), std::string::npos) << k;
}

TEST(IdlJson, FieldsComeInTheIdlsOrderAndMeshFloatsAsTheirShortestText) {
  ForceFeedback f;
  f.valid_radius_m(0.004);
  const std::string j = to_json(f);
  const char* order[] = {"source",   "device",     "answers_seq",   "stamp",
                         "force",    "in_contact", "penetration_m", "stiffness_n_per_m",
                         "position", "jacobian",   "normal",        "valid_radius_m"};
  std::size_t at = 0;
  for (const char* k : order) {
    const std::size_t p = j.find(std::string("\"") + k + "\":", at);
    ASSERT_NE(p, std::string::npos) << k << " missing or out of order in " << j;
    at = p;
  }
  DeformedMesh m;
  m.positions({0.1f, -2.5f, std::nanf("")});
  EXPECT_NE(to_json(m).find(R"("positions":[0.1,-2.5,null])"), std::string::npos) << to_json(m);
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
