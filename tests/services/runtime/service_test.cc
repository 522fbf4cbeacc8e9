// A service's options and loop: the step and its rate, a real-time run's
// duration and overruns, rejected samples counted, and the status it says.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "services/runtime/service.h"

namespace hcosim::services::runtime {
namespace {

// Every in-process DDS test gets its own domain so ctest -j stays safe.
constexpr int kServiceDomain = 30;

Options options(double rate, double duration) {
  Options o;
  o.name = "unit";
  o.domain = kServiceDomain;
  o.rate_hz = rate;
  o.step_s = 1.0 / rate;
  o.duration_s = duration;
  o.qos_file = default_qos_file();
  return o;
}

std::vector<char*> argv_of(std::vector<std::string>& args) {
  std::vector<char*> v;
  for (auto& a : args) v.push_back(a.data());
  return v;
}

// service_main's exit status for `args`, and the options it ran with.
int main_of(std::vector<std::string> args, Options* ran = nullptr) {
  auto v = argv_of(args);
  return service_main("svc", "a test service", int(v.size()), v.data(), [&](const Options& o) {
    if (ran) *ran = o;
    return 0;
  });
}

TEST(Options, ParsesAndDefaultsTheStep) {
  Options o;
  ASSERT_EQ(main_of({"svc", "--name", "a", "--rate", "250", "--domain", "9", "--mode", "lockstep"}, &o), 0);
  EXPECT_EQ(o.name, "a");
  EXPECT_EQ(o.domain, 9);
  EXPECT_EQ(o.mode, adapters::Mode::kLockstep);
  EXPECT_DOUBLE_EQ(o.step_s, 0.004);
  EXPECT_EQ(o.qos_file, default_qos_file());
}

TEST(Options, RefusesMissingAndMalformedValues) {
  for (std::vector<std::string> args :
       std::vector<std::vector<std::string>>{{"svc", "--rate", "100"},
                                             {"svc", "--name", "a"},
                                             {"svc", "--name", "a", "--rate", "fast"},
                                             {"svc", "--name", "a", "--rate", "nan"},
                                             {"svc", "--name", "a", "--rate", "0"},
                                             {"svc", "--name", "a", "--rate", "10", "--bogus", "1"},
                                             {"svc", "--name", "a", "--rate", "10", "--mode", "sometimes"},
                                             {"svc", "--name", "a", "--rate", "10", "--priority", "1.5"},
                                             {"svc", "--name", "a", "--rate", "10", "--domain", "300"},
                                             {"svc", "--name", "a", "--rate"}}) {
    Options o;
    EXPECT_EQ(main_of(args, &o), 2) << args.back();
    EXPECT_TRUE(o.name.empty()) << "ran with " << args.back();
  }
}

TEST(Options, HelpRunsNothing) {
  Options o;
  EXPECT_EQ(main_of({"svc", "--help"}, &o), 0);
  EXPECT_TRUE(o.name.empty());
}

TEST(Service, LockstepRateMustDivideTheBaseStep) {
  Options o = options(300, 0);
  o.step_s = 0.001;
  o.mode = adapters::Mode::kLockstep;
  EXPECT_THROW(Service s(o), std::invalid_argument);
}

// A 30 fps camera under a 1 ms base step: in real time any rate goes, and
// each step is stamped with the base step it falls in.
TEST(Service, RealtimeRateNeedNotDivideTheBaseStep) {
  Options o = options(30, 0.15);
  o.step_s = 0.001;
  Service svc(o);
  std::vector<std::uint64_t> steps;
  std::vector<std::int64_t> times;
  svc.run([&](const Tick& t) { steps.push_back(t.step), times.push_back(t.sim_time_ns); });
  ASSERT_GE(steps.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(steps[i], std::uint64_t(std::llround(i * 1000.0 / 30))) << i;
    EXPECT_EQ(times[i], std::int64_t(i) * std::llround(1e9 / 30)) << i;
  }
}

TEST(Service, FinishEndsARealtimeRunAfterTheCurrentStep) {
  Service svc(options(200, 5));
  int steps = 0;
  EXPECT_EQ(svc.run([&](const Tick&) {
    if (++steps == 3) svc.finish();
  }),
            0);
  EXPECT_EQ(steps, 3);
}

TEST(Service, RealtimeRunStopsAtTheDurationWithConsecutiveSteps) {
  Service svc(options(200, 0.1));
  std::vector<std::uint64_t> steps;
  EXPECT_EQ(svc.run([&](const Tick& t) { steps.push_back(t.step); }), 0);
  ASSERT_GE(steps.size(), 5u);
  EXPECT_LE(steps.size(), 20u);
  EXPECT_EQ(steps.front(), 0u);
  for (std::size_t i = 1; i < steps.size(); ++i) EXPECT_GT(steps[i], steps[i - 1]);
}

TEST(Service, SlowStepsAreCountedAsOverrunsAndSkipped) {
  Service svc(options(100, 0.2));
  std::vector<std::uint64_t> steps;
  svc.run([&](const Tick& t) {
    steps.push_back(t.step);
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
  });
  // 25 ms steps at 100 Hz: each one overruns, and the missed ticks are skipped, not queued.
  ASSERT_GE(steps.size(), 2u);
  EXPECT_LE(steps.size(), 9u);
  EXPECT_GE(steps[1] - steps[0], 2u);
}

TEST(Service, RejectedSamplesAreCountedNotDelivered) {
  Service svc(options(100, 0));
  Reader<HapticState> reader = svc.reader<HapticState>();
  Writer<HapticState> writer(svc.participant());
  // Same participant: intraprocess delivery, still through validation.
  const std::int64_t deadline = mono_ns() + 5'000'000'000;
  while (writer.matched() < 1 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  HapticState bad;
  bad.orientation().w(1);
  bad.position().y(std::nan(""));
  writer.write(bad);
  std::size_t admitted = 0;
  ASSERT_TRUE(reader.wait(std::chrono::seconds(5)));
  admitted += reader.take([](const HapticState&) {});
  HapticState good;
  good.orientation().w(1);
  writer.write(good);
  ASSERT_TRUE(reader.wait(std::chrono::seconds(5)));
  admitted += reader.take([](const HapticState&) {});
  EXPECT_EQ(admitted, 1u);
}

// A reader that joins after the constructor still learns at once that the
// service is starting (the status topic keeps its last reports for late
// joiners); the loop's first step says running, its end stopping. The
// reader keeps the writer's 16 reports: with the profile's 1 a test thread
// descheduled past the run's end (CI, beside the parallel suite) finds only
// "stopping", which a monitor of state may, but this test of the sequence
// may not.
TEST(Service, StatusSaysStartingThenRunningThenStopping) {
  Service svc(options(100, 0.3));
  Reader<ServiceStatus> status(svc.participant(), nullptr, nullptr, TopicOf<ServiceStatus>::qos, 16);
  std::vector<std::string> states;
  std::vector<double> rates;
  auto collect = [&] {
    status.take([&](const ServiceStatus& s) {
      states.push_back(s.state().to_string()), rates.push_back(s.rate_achieved_hz());
    });
  };
  ASSERT_TRUE(status.wait(std::chrono::seconds(5)));
  collect();
  ASSERT_EQ(states, std::vector<std::string>{"starting"});
  EXPECT_EQ(svc.run([&](const Tick&) { collect(); }), 0);
  while (states.back() != "stopping" && status.wait(std::chrono::seconds(5))) collect();
  const auto running = std::find(states.begin(), states.end(), "running");
  ASSERT_NE(running, states.end());
  EXPECT_EQ(states.back(), "stopping");
  // One step after the start-up report is no period: no rate yet (1 step in
  // a few ms would read as hundreds of Hz); the last report has one.
  EXPECT_EQ(rates[running - states.begin()], 0.0);
  EXPECT_GT(rates.back(), 0.0);
}

}  // namespace
}  // namespace hcosim::services::runtime
