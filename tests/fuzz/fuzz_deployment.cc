// Deployment YAML (adapters/deployment.h): every service, param and scene
// key the launcher reads.
#include "adapters/deployment.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".yaml");
  return hcosim::fuzz::refuse_or_accept([&] { hcosim::adapters::load_deployment(path); });
}
