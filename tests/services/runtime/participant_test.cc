// A participant refuses a bad domain and QoS file; lockstep readers hold
// samples until their step.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "services/runtime/endpoint.h"
#include "services/runtime/participant.h"
#include "services/runtime/service.h"

namespace hcosim::services::runtime {
namespace {

// Every in-process DDS test gets its own domain so ctest -j stays safe.
constexpr int kDomain = 151;

TEST(Participant, RefusesABadDomainAndQosFile) {
  EXPECT_THROW(Participant(233, "x"), std::runtime_error);
  EXPECT_THROW(Participant(kDomain, "x", "/nonexistent.xml"), std::runtime_error);
}

// A lockstep step sees only samples stamped before it, in step order,
// whatever order they were written in; later ones wait for their step.
TEST(Participant, LockstepReadersHoldSamplesUntilTheirStep) {
  Participant p(kDomain, "unit_lockstep", default_qos_file(), nullptr, true);
  Reader<HapticState> reader(p);
  Writer<HapticState> writer(p);
  const std::int64_t deadline = mono_ns() + 5'000'000'000;
  while (writer.matched() < 1 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  for (const std::uint64_t step : {3, 1, 5, 2}) {
    HapticState s;
    s.orientation().w(1);
    s.stamp().step(step);
    writer.write(s);
  }
  // Reliable in lockstep: acknowledged means in the reader's history.
  ASSERT_TRUE(writer.wait_acknowledged(std::chrono::seconds(5)));
  std::vector<std::uint64_t> got;
  reader.take_before(3, [&](const HapticState& s) { got.push_back(s.stamp().step()); });
  EXPECT_EQ(got, (std::vector<std::uint64_t>{1, 2}));
  got.clear();
  reader.take_before(3, [&](const HapticState& s) { got.push_back(s.stamp().step()); });
  EXPECT_TRUE(got.empty());
  reader.take_before(6, [&](const HapticState& s) { got.push_back(s.stamp().step()); });
  EXPECT_EQ(got, (std::vector<std::uint64_t>{3, 5}));
}

// Under the network's bulk cap, large samples' writers send paced (through
// its flow controller), the haptic topics' never; without it, none is.
TEST(Participant, TheBulkCapPacesLargeSamplesOnly) {
  Network capped;
  capped.bulk_bytes_per_s = 1e6;
  Participant p(kDomain, "unit_paced", default_qos_file(), nullptr, false, {}, capped);
  EXPECT_TRUE(Writer<DeformedMesh>(p).paced());
  EXPECT_TRUE(Writer<CameraFrame>(p).paced());
  EXPECT_FALSE(Writer<ForceFeedback>(p).paced());
  Writer<DeformedMesh> w(p);
  EXPECT_TRUE(w.caught_up()) << "nothing written, nothing to acknowledge";
  Participant q(kDomain, "unit_unpaced");
  EXPECT_FALSE(Writer<DeformedMesh>(q).paced());
}

}  // namespace
}  // namespace hcosim::services::runtime
