// The bridge's process (services/foxglove/bridge.h): a camera frame's
// buffer comes from the heap and is kept there once freed, rather than
// mapped afresh and given back for each frame.
#include "services/foxglove/bridge.h"

#include <malloc.h>

#include <cstdlib>

#include <gtest/gtest.h>

namespace hcosim::services::foxglove {
namespace {

// glibc's mmap threshold starts at 128 KB: a 900 KB frame is a mapping of
// its own until keep_freed_memory(), then heap memory that outlives it.
TEST(FoxgloveBridge, ACameraFramesBufferIsHeapMemoryKeptForTheNext) {
  constexpr std::size_t kFrame = 640 * 480 * 3;
  keep_freed_memory();
  const std::size_t mapped = mallinfo2().hblkhd;
  void* frame = std::malloc(kFrame);
  ASSERT_NE(frame, nullptr);
  static_cast<volatile char*>(frame)[kFrame - 1] = 1;
  EXPECT_EQ(mallinfo2().hblkhd, mapped) << "the frame was mapped on its own";
  const std::size_t heap = mallinfo2().arena;
  std::free(frame);
  EXPECT_EQ(mallinfo2().arena, heap) << "the freed frame was given back to the kernel";
}

}  // namespace
}  // namespace hcosim::services::foxglove
