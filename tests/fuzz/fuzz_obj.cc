// Wavefront OBJ meshes (models/massspring/mesh_lattice.h), then the checks
// a mesh object runs before it is voxelised.
#include "models/massspring/mesh_lattice.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = hcosim::fuzz::scratch(data, size, ".obj");
  return hcosim::fuzz::refuse_or_accept([&] {
    hcosim::models::massspring::TriangleMesh m = hcosim::models::massspring::read_obj(path);
    hcosim::models::massspring::weld(m, 1e-9);
    hcosim::models::massspring::check_closed(m);
  });
}
