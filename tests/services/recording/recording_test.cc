// Recordings in either format hold the samples as they were serialised,
// with their topic, step, simulated and receive times; an MCAP recording's
// channels carry each topic's IDL type as a self-contained schema, and a
// file from elsewhere is read for the contract's topics only.
#include "services/recording/recording.h"

#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::services::recording {
namespace {

std::string recording_temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("hcosim_recording_test_" + name)).string();
}

std::vector<Record> samples() {
  std::vector<Record> out;
  for (int k = 0; k < 5; ++k) {
    HapticState h;
    h.device("omni");
    h.seq(k);
    h.stamp().step(10 + k);
    h.stamp().sim_time_ns(1000000ll * (10 + k));
    h.stamp().wall_time_ns(1700000000000000000ll + k);
    h.position().z(0.01 * k);
    out.push_back(make_record(h, 1700000000000000500ll + 1000 * k));
    DeformedMesh m;
    m.mesh("cube");
    m.stamp().step(10 + k);
    m.stamp().sim_time_ns(1000000ll * (10 + k));
    m.positions(std::vector<float>(3 * 100, 0.5f + k));
    out.push_back(make_record(m, 1700000000000000600ll + 1000 * k));
  }
  ClockTick t;
  t.step(99);
  out.push_back(make_record(t, 1700000000000009000ll));
  return out;
}

class RecordingFormats : public testing::TestWithParam<RecordingFormat> {};

TEST_P(RecordingFormats, RecordsReadBackAsWritten) {
  const std::string path = recording_temp(GetParam() == RecordingFormat::mcap ? "r.mcap" : "r.rec");
  const std::vector<Record> in = samples();
  RecordingWriter w(path);
  for (const Record& r : in) w.write(r);
  w.close();
  EXPECT_EQ(w.count(), in.size());
  RecordingReader reader(path);
  std::size_t n = 0;
  for (Record r; reader.next(r); ++n) {
    ASSERT_LT(n, in.size());
    EXPECT_EQ(r.topic, in[n].topic);
    EXPECT_EQ(r.step, in[n].step);
    EXPECT_EQ(r.sim_time_ns, in[n].sim_time_ns);
    EXPECT_EQ(r.receive_ns, in[n].receive_ns);
    EXPECT_EQ(r.cdr, in[n].cdr) << "record " << n;
  }
  EXPECT_EQ(n, in.size());
  EXPECT_EQ(in[0].publish_ns, 1700000000000000000ll);  // the stamp's wall time
  EXPECT_EQ(in.back().step, 99u);
  std::remove(path.c_str());
}

INSTANTIATE_TEST_SUITE_P(Both, RecordingFormats, testing::Values(RecordingFormat::hcosim, RecordingFormat::mcap),
                         [](const auto& p) { return p.param == RecordingFormat::mcap ? "mcap" : "hcosim"; });

// Each channel: the topic, CDR, and a schema named by the type's scoped
// name holding every type it uses, with no #include left.
TEST(Recording, McapChannelsCarryTheirTypesAsSelfContainedIdl) {
  const std::string path = recording_temp("schemas.mcap");
  RecordingWriter w(path, RecordingFormat::mcap, McapCompression::lz4);
  for (const Record& r : samples()) w.write(r);
  w.close();
  McapReader r(path);
  for (McapMessage m; r.next(m);) {
  }
  ASSERT_EQ(r.channels().size(), 3u);
  for (const auto& [id, c] : r.channels()) {
    const McapSchema& s = r.schemas().at(c.schema_id);
    EXPECT_EQ(c.message_encoding, "cdr");
    EXPECT_EQ(s.encoding, "omgidl");
    EXPECT_EQ(s.name, c.topic == "HapticState"    ? "hcosim::HapticState"
                      : c.topic == "DeformedMesh" ? "hcosim::DeformedMesh"
                                                  : "hcosim::ClockTick");
    EXPECT_EQ(s.data.find("#include"), std::string::npos);
    EXPECT_NE(s.data.find("struct " + s.name.substr(8) + " {"), std::string::npos);
    EXPECT_NE(s.data.find("struct StepStamp {"), std::string::npos);
  }
  EXPECT_EQ(idl_schema("hcosim::Vec3"), idl_schema("hcosim::Quat"));  // common.idl alone
  EXPECT_NE(tests::message_of([] { idl_schema("hcosim::Jelly"); }).find("no IDL file declares 'hcosim::Jelly'"),
            std::string::npos);
  std::remove(path.c_str());
}

// An MCAP file from elsewhere: channels of other topics or encodings are
// skipped and counted; a contract topic under another schema is refused.
TEST(Recording, AForeignMcapIsReadForTheContractsTopicsOnly) {
  const std::string path = recording_temp("foreign.mcap");
  const Record h = samples()[0];
  {
    McapWriter w(path, McapCompression::zstd);
    const std::uint16_t ours = w.add_schema("hcosim::HapticState", "omgidl", idl_schema("hcosim::HapticState"));
    const std::uint16_t theirs = w.add_schema("foxglove.Log", "jsonschema", "{}");
    const std::uint16_t a = w.add_channel(ours, "HapticState", "cdr"), b = w.add_channel(theirs, "/log", "json");
    const std::uint16_t c = w.add_channel(ours, "HapticState", "json");
    for (const std::uint16_t ch : {b, a, c, a}) {
      McapMessage m;
      m.channel = ch, m.log_time = 5, m.data = h.cdr;
      w.write(m);
    }
    w.close();
  }
  RecordingReader r(path);
  int n = 0;
  for (Record rec; r.next(rec); ++n) {
    EXPECT_EQ(rec.topic, "HapticState");
    EXPECT_EQ(rec.step, h.step);
    EXPECT_EQ(rec.receive_ns, 5);
  }
  EXPECT_EQ(n, 2);
  EXPECT_EQ(r.skipped(), 2u);
  {
    McapWriter w(path, McapCompression::none);
    const std::uint16_t s = w.add_schema("other::HapticState", "omgidl", "struct HapticState { long a; };");
    McapMessage m;
    m.channel = w.add_channel(s, "HapticState", "cdr"), m.data = h.cdr;
    w.write(m);
    w.close();
  }
  EXPECT_NE(tests::message_of([&] {
              RecordingReader bad(path);
              for (Record rec; bad.next(rec);) {
              }
            })
                .find("channel 1 'HapticState' has schema 'other::HapticState'; hcosim's HapticState is "
                      "hcosim::HapticState"),
            std::string::npos);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace hcosim::services::recording
