// Little-endian values in byte strings: the layout the recording formats
// and MCAP specify, and what is written reads back.
#include "services/recording/bytes.h"

#include <cstdint>

#include <gtest/gtest.h>

namespace hcosim::services::recording {
namespace {

TEST(Bytes, ValuesAreLaidOutLowByteFirstAndReadBack) {
  std::string s;
  append_le(s, std::uint32_t(0x01020304));
  append_le(s, std::int16_t(-2));
  append_le(s, 0.5);
  ASSERT_EQ(s.size(), 4u + 2u + 8u);
  EXPECT_EQ(s.substr(0, 6), std::string("\x04\x03\x02\x01\xfe\xff", 6));
  const char* p = s.data();
  EXPECT_EQ(read_le<std::uint32_t>(p), 0x01020304u);
  EXPECT_EQ(read_le<std::int16_t>(p), -2);
  EXPECT_EQ(read_le<double>(p), 0.5);
  EXPECT_EQ(p, s.data() + s.size());
}

}  // namespace
}  // namespace hcosim::services::recording
