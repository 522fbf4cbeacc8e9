#include "models/mjcf/load.h"

#include <cstring>
#include <memory>
#include <stdexcept>

namespace hcosim::models::mjcf {

void load(const std::string& who, const std::string& xml, mjModel*& model, mjData*& data) {
  // mjVFS holds 2000 file names inline (about 2 MB): too large for the stack.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), "model.xml", int(xml.size())) != 0)
    throw std::runtime_error(who + ": cannot make the in-memory file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), "model.xml")], xml.data(), xml.size());
  char error[1000] = "";
  model = mj_loadXML("model.xml", vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!model) throw std::runtime_error(who + ": MuJoCo refused the model: " + error);
  data = mj_makeData(model);
  if (!data) {
    mj_deleteModel(model);
    model = nullptr;
    throw std::runtime_error(who + ": cannot allocate mjData");
  }
}

}  // namespace hcosim::models::mjcf
