// The haptic device's servo loop without DDS: the state it publishes, the
// answers it waits for, what it renders when one is late and how far that
// was off once it comes, free-space answers it need not wait for, another
// device's answers ignored, the Gauss-Seidel group's step, and a source
// that falls silent.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "adapters/device/haptic_idl.h"
#include "services/haptic/servo_loop.h"
#include "tests/support/samples.h"
#include "tests/support/temp_dir.h"

namespace hcosim::services::haptic {
namespace {

// A stylus held still at [0, 0, 0.06] for a second: a replayed recording,
// which the forces rendered do not move.
adapters::device::DeviceConfig still_stylus(const tests::TempDir& dir) {
  dir.file("still.csv", "time_s,x,y,z,buttons\n0,0,0,0.06,0\n1,0,0,0.06,0\n");
  const std::string params = dir.file("params.yaml", "device: replay\nreplay: still.csv\npassivity: off\n");
  return adapters::device::device_config(adapters::Config::load(params, "params"), 1000);
}

runtime::Tick tick(std::uint64_t k) { return {k, std::int64_t(k) * 1'000'000, 1e-3, 0}; }

using tests::stamp;

// `source`'s answer to state `seq`: 1 N up in contact (a 500 N/m spring)
// at the stylus, or a free-space model of 5 cm.
ForceFeedback contact(const std::string& source, std::uint64_t seq, const std::string& device = "omni") {
  const Eigen::Vector3d at(0, 0, 0.06);
  return adapters::device::force_feedback(
      source, device, seq, stamp(seq),
      adapters::device::contact_feel(Eigen::Vector3d(0, 0, 1), at, Eigen::Vector3d::UnitZ(), 500, 0.002, 0.002));
}
ForceFeedback free_space(const std::string& source, std::uint64_t seq) {
  return adapters::device::force_feedback(source, "omni", seq, stamp(seq),
                                          adapters::device::free_feel(Eigen::Vector3d(0, 0, 0.06), 0.05));
}

TEST(ServoLoop, AnAnswerInTheTickIsRenderedAndALateOneIsModelledThenMeasured) {
  tests::TempDir dir;
  ServoLoop loop(still_stylus(dir), "omni", {}, false, stderr);
  HapticState s = loop.begin(tick(0), stamp(0));
  EXPECT_EQ(s.device().to_string(), "omni");
  EXPECT_EQ(s.seq(), 0u);
  EXPECT_NEAR(s.position().z(), 0.06, 1e-6);
  loop.expect();
  EXPECT_FALSE(loop.waiting()) << "no source has answered yet: none is waited for";
  loop.take(contact("cube", 0), 0);
  loop.end();
  EXPECT_NEAR(adapters::device::from_idl(loop.begin(tick(1), stamp(1)).rendered_force()).z(), 1, 1e-9)
      << "the next state carries the force rendered: the cube's";
  loop.expect();
  EXPECT_TRUE(loop.waiting()) << "the cube answered in contact: it is waited for";
  loop.end();  // its answer is late: its local model stands in
  loop.begin(tick(2), stamp(2));
  loop.take(contact("cube", 1), 2);  // the late answer: what was rendered, against it
  loop.take(contact("cube", 2), 2);
  loop.expect();
  EXPECT_FALSE(loop.waiting());
  loop.end();
  EXPECT_NEAR(loop.in_tick_ratio(), 0.5, 1e-12) << "tick 1 waited in vain, tick 2 did not";
  EXPECT_NEAR(loop.force_error_p99(), 0, 1e-9) << "the local model stood in exactly for a still stylus";
  const std::string json = loop.report_json();
  EXPECT_NE(json.find("\"ticks\":3"), std::string::npos) << json;
  EXPECT_NE(json.find("\"modelled\":1"), std::string::npos) << json;
  EXPECT_NE(json.find("\"late_answers\":1"), std::string::npos) << json;
}

TEST(ServoLoop, AFreeSpaceAnswerIsNotWaitedForAndAnotherDevicesIsIgnored) {
  tests::TempDir dir;
  ServoLoop loop(still_stylus(dir), "omni", {}, false, stderr);
  loop.begin(tick(0), stamp(0));
  loop.take(free_space("sheet", 0), 0);
  loop.take(contact("cube", 0, "other"), 0);
  loop.expect();
  EXPECT_FALSE(loop.waiting());
  loop.end();
  for (std::uint64_t k = 1; k < 5; ++k) {
    const HapticState s = loop.begin(tick(k), stamp(k));
    EXPECT_EQ(adapters::device::from_idl(s.rendered_force()).norm(), 0) << "nothing but free space: no force";
    loop.expect();
    EXPECT_FALSE(loop.waiting()) << "the sheet's free-space model covers the stylus, tick " << k;
    loop.end();
  }
  // Every tick's, the first's too: its answer came before it asked.
  EXPECT_NE(loop.report_json().find("\"covered\":5"), std::string::npos) << loop.report_json();
}

TEST(ServoLoop, TheGroupAnswersEachStepAndOthersCountAtTheNext) {
  tests::TempDir dir;
  ServoLoop loop(still_stylus(dir), "omni", {"cube"}, true, stderr);
  ASSERT_TRUE(loop.gauss_seidel());
  loop.begin(tick(0), stamp(0));
  EXPECT_TRUE(loop.waiting()) << "the group is waited for from the first step";
  loop.take(contact("sheet", 0), 0);  // from outside the group: the next step's
  EXPECT_TRUE(loop.waiting());
  loop.take(contact("cube", 0), 0);
  EXPECT_FALSE(loop.waiting());
  loop.end();
  const HapticState next = loop.begin(tick(1), stamp(1));
  EXPECT_NEAR(adapters::device::from_idl(next.rendered_force()).z(), 1, 1e-9) << "step 0 rendered the cube's alone";
  loop.take(contact("cube", 1), 1);
  loop.end();
  EXPECT_NEAR(adapters::device::from_idl(loop.begin(tick(2), stamp(2)).rendered_force()).z(), 2, 1e-9)
      << "step 1 rendered the cube's and, a step late, the sheet's";
  EXPECT_EQ(loop.in_tick_ratio(), 1);
}

TEST(ServoLoop, ASilentSourceDropsOutAndIsSaidToBe) {
  tests::TempDir dir;
  const std::string said = tests::written([&](std::FILE* log) {
    ServoLoop loop(still_stylus(dir), "omni", {}, false, log);
    loop.begin(tick(0), stamp(0));
    loop.take(contact("cube", 0), 0);
    loop.end();
    // The default source timeout is 50 ms: a hundred ticks of silence.
    std::uint64_t k = 1;
    for (; k < 100; ++k) loop.begin(tick(k), stamp(k)), loop.expect(), loop.end();
    EXPECT_EQ(adapters::device::from_idl(loop.begin(tick(k), stamp(k)).rendered_force()).norm(), 0)
        << "its force is zero, not its last";
    loop.take(contact("cube", k), k);
    loop.end();
  });
  EXPECT_NE(said.find("omni: source 'cube' fell silent"), std::string::npos) << said;
  EXPECT_NE(said.find("omni: source 'cube' answers again"), std::string::npos) << said;
}

}  // namespace
}  // namespace hcosim::services::haptic
