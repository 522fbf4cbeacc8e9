// Deployment YAML (runtime/deployment.h): every service, param and scene
// key the launcher reads.
#include "services/runtime/deployment.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".yaml");
  return hcosim::fuzz::refuse_or_accept([&] { hcosim::services::runtime::load_deployment(path); });
}
