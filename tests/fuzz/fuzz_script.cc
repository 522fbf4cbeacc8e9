// Haptic scripts (adapters/device/script_yaml.h), the scripted stylus.
#include "adapters/device/script_yaml.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".yaml");
  return hcosim::fuzz::refuse_or_accept([&] { hcosim::adapters::device::load_script(path); });
}
