// A participant refuses a bad domain and QoS file; lockstep readers hold
// samples until their step; an in-process reader is handed samples inside
// write.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "services/runtime/endpoint.h"
#include "services/runtime/participant.h"
#include "services/runtime/service.h"

namespace hcosim::services::runtime {
namespace {

// Every in-process DDS test gets its own domain so ctest -j stays safe.
constexpr int kParticipantDomain = 30;

TEST(Participant, RefusesABadDomainAndQosFile) {
  EXPECT_THROW(Participant(233, "x"), std::runtime_error);
  EXPECT_THROW(Participant(kParticipantDomain, "x", "/nonexistent.xml"), std::runtime_error);
}

// A lockstep step sees only samples stamped before it, in step order,
// whatever order they were written in; later ones wait for their step.
// Linux's default ephemeral ports are 32768 to 60999: a domain's 250
// ports from 7400 + 250 * domain meet them from domain 101 to 214.
TEST(Participant, SaysWhichDomainsPortsMeetTheEphemeralOnes) {
  for (const int clear : {0, 100, 215, adapters::kMaxDomain})
    EXPECT_FALSE(in_ephemeral_range(clear, 32768, 60999)) << clear;
  for (const int inside : {101, 168, 214}) EXPECT_TRUE(in_ephemeral_range(inside, 32768, 60999)) << inside;
  EXPECT_FALSE(in_ephemeral_range(168, 0, -1)) << "a range that could not be read warns of nothing";
  const auto [lo, hi] = ephemeral_ports();
  EXPECT_TRUE(hi == -1 || (lo > 0 && lo <= hi && hi <= 65535)) << lo << " to " << hi;
}

TEST(Participant, LockstepReadersHoldSamplesUntilTheirStep) {
  Participant p(kParticipantDomain, "unit_lockstep", default_qos_file(), nullptr, true);
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

// A reader in the writer's process is handed each sample on the writer's
// thread, inside write, and writing() says so there (the Foxglove bridge's
// receiving threads rest, but never a writer's); outside a write it is false.
TEST(Participant, AnInProcessReaderIsHandedSamplesInsideWrite) {
  Participant p(kParticipantDomain, "unit_writing");
  Reader<HapticState> reader(p, {}, nullptr, "control");
  Writer<HapticState> writer(p);
  const std::int64_t deadline = mono_ns() + 5'000'000'000;
  while (writer.matched() < 1 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const std::thread::id here = std::this_thread::get_id();
  int inside = 0, elsewhere = 0;
  reader.on_arrival([&] {
    reader.take([&](const HapticState&) { ++(writing() && std::this_thread::get_id() == here ? inside : elsewhere); });
  });
  for (int k = 0; k < 3; ++k) {
    HapticState s;
    s.orientation().w(1);
    s.seq(std::uint64_t(k));
    ASSERT_TRUE(writer.write(s));
  }
  reader.on_arrival(nullptr);
  EXPECT_EQ(inside, 3);
  EXPECT_EQ(elsewhere, 0);
  EXPECT_FALSE(writing());
}

// In lockstep the step protocol's writers keep their last samples once
// acknowledged (TRANSIENT_LOCAL, endpoint.h: kept_in_lockstep), which a
// durable reader joining later receives, in order; other state writers
// remove them (VOLATILE), and such a reader does not even match them.
TEST(Participant, LockstepClockWritersKeepTheirLastSamples) {
  using namespace eprosima::fastdds::dds;
  Participant p(kParticipantDomain, "unit_kept", default_qos_file(), nullptr, true);
  Reader<ClockTick> now(p);
  Writer<ClockTick> ticks(p);
  Writer<RigidBodyState> bodies(p);
  const std::int64_t deadline = mono_ns() + 5'000'000'000;
  while (ticks.matched() < 1 && mono_ns() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  for (std::uint64_t step = 0; step < 20; ++step) {
    ClockTick t;
    t.step(step);
    ticks.write(t);
    ASSERT_TRUE(ticks.wait_acknowledged(std::chrono::seconds(5)));
  }
  DataReaderQos qos;
  p.subscriber()->get_datareader_qos_from_profile("sequence", qos);
  qos.reliability().kind = RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
  DataReader* late = p.subscriber()->create_datareader(p.topic<ClockTick>(), qos);
  DataReader* late_bodies = p.subscriber()->create_datareader(p.topic<RigidBodyState>(), qos);
  ASSERT_TRUE(late && late_bodies);
  std::vector<std::uint64_t> got;
  ClockTick t;
  SampleInfo info;
  while (got.size() < 8 && mono_ns() < deadline + 5'000'000'000) {
    while (late->take_next_sample(&t, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) got.push_back(t.step());
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(got, (std::vector<std::uint64_t>{12, 13, 14, 15, 16, 17, 18, 19}));  // "sequence": KEEP_LAST 8
  EXPECT_EQ(bodies.matched(), 0);
  p.subscriber()->delete_datareader(late);
  p.subscriber()->delete_datareader(late_bodies);
}

// Under the network's bulk cap, large samples' writers send paced (through
// its flow controller), the haptic topics' never; without it, none is.
TEST(Participant, TheBulkCapPacesLargeSamplesOnly) {
  Network capped;
  capped.bulk_bytes_per_s = 1e6;
  Participant p(kParticipantDomain, "unit_paced", default_qos_file(), nullptr, false, {}, capped);
  EXPECT_TRUE(Writer<DeformedMesh>(p).paced());
  EXPECT_TRUE(Writer<CameraFrame>(p).paced());
  EXPECT_FALSE(Writer<ForceFeedback>(p).paced());
  Writer<DeformedMesh> w(p);
  EXPECT_TRUE(w.caught_up()) << "nothing written, nothing to acknowledge";
  Participant q(kParticipantDomain, "unit_unpaced");
  EXPECT_FALSE(Writer<DeformedMesh>(q).paced());
}

}  // namespace
}  // namespace hcosim::services::runtime
