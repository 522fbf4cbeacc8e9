// A recorded trajectory plays back at the servo rate, interpolated, with
// its buttons.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "adapters/device/replay.h"

namespace hcosim::adapters::device {

using namespace models::haptic;
namespace {

// A recording plays back at the servo rate, interpolated, with its
// buttons; forces do not move it but are still clamped and counted.
TEST(HapticDevice, ReplayPlaysTheRecordingBack) {
  const auto path = std::filesystem::temp_directory_path() / ("hcosim_replay_" + std::to_string(::getpid()) + ".csv");
  std::ofstream(path) << "time_s,x,y,z,buttons\n0,0,0,0,0\n0.01,0.001,0,0,1\n0.02,0.001,0.002,0,0\n";
  Replay r({}, load_trajectory(path.string()));
  std::vector<Frame> frames;
  while (!r.finished()) frames.push_back(r.begin_frame()), r.end_frame({0, 0, 9});
  ASSERT_EQ(frames.size(), 21u);
  EXPECT_NEAR(frames[5].position.x(), 0.0005, 1e-12);
  EXPECT_NEAR(frames[5].velocity.x(), 0.1, 1e-9);
  EXPECT_EQ(frames[12].buttons, 1u);
  EXPECT_NEAR(frames[15].position.y(), 0.001, 1e-12);
  EXPECT_EQ(r.saturated(), 21u);
  // Errors name the file and line.
  std::ofstream(path) << "time_s,x,y,z,buttons\n0,0,0,0,0\n0,1,0,0,0\n";
  try {
    load_trajectory(path.string());
    ADD_FAILURE() << "accepted a time that does not increase";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(".csv:3: time does not increase"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hcosim::adapters::device
