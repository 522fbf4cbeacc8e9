// The MCAP codec: what it writes reads back in order under every
// compression, the summary that seeking readers use points at the records
// it names (read here from the footer by the specification's layout, not
// through the reader), and corrupt, cut-short and foreign files are named
// with the place they go wrong. An independent reader, MCAP's own
// @mcap/core, reads hcosim's recordings in integration.mcap.
#include "services/recording/mcap.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::services::recording {
namespace {

std::string mcap_temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("hcosim_mcap_test_" + name)).string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

template <class U>
U at(const std::string& s, std::size_t offset) {
  U v;
  std::memcpy(&v, s.data() + offset, sizeof(U));
  return v;
}

McapMessage message(std::uint16_t channel, std::uint32_t seq, std::uint64_t t, std::size_t bytes) {
  McapMessage m;
  m.channel = channel, m.sequence = seq, m.log_time = t, m.publish_time = t - 7;
  for (std::size_t i = 0; i < bytes; ++i) m.data.push_back(std::uint8_t(i * 31 + seq));
  return m;
}

// Two channels, 300 messages of up to 5 kB: several 64 kB chunks.
std::vector<McapMessage> write_sample(const std::string& path, McapCompression c) {
  McapWriter w(path, c, 64 << 10);
  const std::uint16_t s = w.add_schema("hcosim::Thing", "omgidl", "module hcosim { struct Thing { long a; }; };");
  const std::uint16_t a = w.add_channel(s, "A", "cdr", {{"k", "v"}});
  const std::uint16_t b = w.add_channel(s, "B", "cdr");
  std::vector<McapMessage> sent;
  for (std::uint32_t i = 0; i < 300; ++i) {
    sent.push_back(message(i % 3 ? a : b, i, 1000000 + 1000ull * i, 40 + 17 * (i % 300)));
    w.write(sent.back());
  }
  w.close();
  return sent;
}

class McapFile : public testing::TestWithParam<McapCompression> {};

TEST_P(McapFile, WhatIsWrittenReadsBackInOrder) {
  const std::string path = mcap_temp(std::string("roundtrip_") + name(GetParam()) + ".mcap");
  const std::vector<McapMessage> sent = write_sample(path, GetParam());
  ASSERT_TRUE(is_mcap(path));
  McapReader r(path);
  std::size_t n = 0;
  for (McapMessage m; r.next(m); ++n) {
    ASSERT_LT(n, sent.size());
    EXPECT_EQ(m.channel, sent[n].channel);
    EXPECT_EQ(m.sequence, sent[n].sequence);
    EXPECT_EQ(m.log_time, sent[n].log_time);
    EXPECT_EQ(m.publish_time, sent[n].publish_time);
    EXPECT_EQ(m.data, sent[n].data) << "message " << n;
  }
  EXPECT_EQ(n, sent.size());
  ASSERT_EQ(r.channels().size(), 2u);
  EXPECT_EQ(r.channels().at(1).topic, "A");
  EXPECT_EQ(r.channels().at(1).metadata.at("k"), "v");
  EXPECT_EQ(r.schemas().at(1).name, "hcosim::Thing");
  EXPECT_EQ(r.schemas().at(1).encoding, "omgidl");
  std::remove(path.c_str());
}

// The footer names the summary; its chunk indexes name each chunk and its
// message indexes, whose entries name every message; the statistics count
// them all. Read by offsets as a seeking reader does.
TEST_P(McapFile, TheSummaryIndexesEveryChunkAndMessage) {
  const std::string path = mcap_temp(std::string("summary_") + name(GetParam()) + ".mcap");
  const std::vector<McapMessage> sent = write_sample(path, GetParam());
  const std::string f = slurp(path);
  ASSERT_EQ(f.substr(f.size() - 8), std::string("\x89MCAP0\r\n", 8));
  const std::size_t footer = f.size() - 8 - 29;
  ASSERT_EQ(std::uint8_t(f[footer]), 0x02);
  const std::uint64_t summary = at<std::uint64_t>(f, footer + 9);
  std::size_t p = summary, chunks = 0, indexed = 0;
  std::uint64_t stats_messages = 0;
  while (p < at<std::uint64_t>(f, footer + 17)) {
    const std::uint8_t op = std::uint8_t(f[p]);
    const std::uint64_t len = at<std::uint64_t>(f, p + 1);
    const std::size_t body = p + 9;
    if (op == 0x0B) stats_messages = at<std::uint64_t>(f, body);
    if (op == 0x08) {
      ++chunks;
      const std::uint64_t chunk = at<std::uint64_t>(f, body + 16);
      EXPECT_EQ(std::uint8_t(f[chunk]), 0x06) << "chunk index " << chunks;
      const std::uint32_t map = at<std::uint32_t>(f, body + 32);
      for (std::size_t e = 0; e < map; e += 10) {
        const std::uint64_t index = at<std::uint64_t>(f, body + 36 + e + 2);
        EXPECT_EQ(std::uint8_t(f[index]), 0x07);
        EXPECT_EQ(at<std::uint16_t>(f, index + 9), at<std::uint16_t>(f, body + 36 + e));
        indexed += at<std::uint32_t>(f, index + 11) / 16;
      }
    }
    p = body + len;
  }
  EXPECT_GT(chunks, 3u);
  EXPECT_EQ(indexed, sent.size());
  EXPECT_EQ(stats_messages, sent.size());
  std::remove(path.c_str());
}

INSTANTIATE_TEST_SUITE_P(Every, McapFile,
                         testing::Values(McapCompression::none, McapCompression::zstd, McapCompression::lz4),
                         [](const auto& p) {
                           return std::string(p.param == McapCompression::none ? "none" : name(p.param));
                         });

TEST(Mcap, CorruptCutShortAndForeignFilesAreNamed) {
  const std::string path = mcap_temp("bad.mcap");
  write_sample(path, McapCompression::none);
  const std::string good = slurp(path);
  auto with = [&](const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    return tests::message_of([&] {
      McapReader r(path);
      for (McapMessage m; r.next(m);) {
      }
    });
  };
  // A byte of the first chunk's records flipped: its CRC no longer matches.
  std::string flipped = good;
  const std::size_t chunk = 8 + 9 + 14;  // after the magic and the header ("", "hcosim")
  ASSERT_EQ(good[chunk], '\x06');
  flipped[chunk + 9 + 8 + 8 + 8 + 4 + 4 + 8 + 40] ^= 0x5a;
  EXPECT_NE(with(flipped).find("the chunk's CRC does not match"), std::string::npos) << with(flipped);
  EXPECT_NE(with(flipped).find("record at byte " + std::to_string(chunk)), std::string::npos);
  EXPECT_NE(with(good.substr(0, good.size() / 2)).find("is cut short"), std::string::npos);
  EXPECT_NE(with("HCOSREC1 and more").find("not an MCAP file"), std::string::npos);
  EXPECT_EQ(with(good), "");
  std::remove(path.c_str());
  EXPECT_NE(tests::message_of([] { McapReader r("/nonexistent/x.mcap"); }).find("cannot be read"), std::string::npos);
  EXPECT_NE(
      tests::message_of([] { McapWriter w("/nonexistent/x.mcap", McapCompression::zstd); }).find("cannot be written"),
      std::string::npos);
  McapWriter w(mcap_temp("misuse.mcap"), McapCompression::none);
  EXPECT_NE(tests::message_of([&] { w.add_channel(1, "A", "cdr"); }).find("names no schema 1"), std::string::npos);
  EXPECT_NE(tests::message_of([&] { w.write(message(1, 0, 10, 4)); }).find("on no channel 1"), std::string::npos);
  w.close();
  std::remove(mcap_temp("misuse.mcap").c_str());
}

}  // namespace
}  // namespace hcosim::services::recording
