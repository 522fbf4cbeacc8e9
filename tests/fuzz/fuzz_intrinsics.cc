// Camera intrinsics files (adapters/vision/calibration.h), read through
// OpenCV's FileStorage.
#include "adapters/vision/calibration.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".yaml");
  return hcosim::fuzz::refuse_or_accept([&] { hcosim::adapters::vision::read_intrinsics(path); });
}
