// Camera intrinsics files (adapters/vision/calibration.h), read through
// OpenCV's FileStorage.
#include "tests/fuzz/fuzz_input.h"
#include "adapters/vision/calibration.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".yaml");
  return hcosim::fuzz::refuse_or_accept([&] { hcosim::adapters::vision::read_intrinsics(path); });
}
