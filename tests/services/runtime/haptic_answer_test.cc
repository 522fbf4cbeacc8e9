// A source answers every state of its device as it arrives, until stopped.
#include <chrono>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "services/runtime/haptic_answer.h"

namespace hcosim::services::runtime {
namespace {

// Every in-process DDS test gets its own domain so ctest -j stays safe.
constexpr int kAnswerDomain = 30;

// A source answers each state of its device as it arrives, with no loop of
// its own running (in one process Fast DDS delivers on the writer's thread;
// between processes, on the receiving one); another device's states are
// not its to answer, and once stopped it answers nothing more.
TEST(AnswerOnArrival, AnswersEveryStateOfItsDeviceAsItArrivesUntilStopped) {
  Participant p(kAnswerDomain, "unit_answer");
  Reader<HapticState> in(p, nullptr, nullptr, "control", 64);
  Writer<HapticState> out(p, "state");  // reliable: none of the states is lost on the way
  std::mutex m;
  std::vector<std::uint64_t> answered;
  auto answers = std::make_unique<AnswerOnArrival>(in, "omni", [&](const HapticState& s) {
    std::lock_guard<std::mutex> l(m);
    answered.push_back(s.seq());
  });
  const std::int64_t deadline = mono_ns() + 5'000'000'000;
  while (out.matched() < 1 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const auto write = [&](const char* device, std::uint64_t seq) {
    HapticState s;
    s.device(device);
    s.seq(seq);
    s.orientation().w(1);
    out.write(s);
  };
  for (std::uint64_t k = 0; k < 20; ++k) {
    write(k % 2 ? "other" : "omni", k);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(out.wait_acknowledged(std::chrono::seconds(5)));
  const auto count = [&] {
    std::lock_guard<std::mutex> l(m);
    return answered.size();
  };
  while (count() < 10 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  answers->stop();
  {
    std::lock_guard<std::mutex> l(m);
    EXPECT_EQ(answered, (std::vector<std::uint64_t>{0, 2, 4, 6, 8, 10, 12, 14, 16, 18}));
  }
  write("omni", 20);
  ASSERT_TRUE(out.wait_acknowledged(std::chrono::seconds(5)));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(count(), 10u) << "answered after stop()";
}

}  // namespace
}  // namespace hcosim::services::runtime
