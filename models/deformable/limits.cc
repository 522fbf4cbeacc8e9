#include "models/deformable/limits.h"

#include <sstream>

namespace hcosim::models::deformable {

std::string Range::text() const {
  std::ostringstream o;
  o << '[' << lo << ", " << hi << ']';
  return o.str();
}

}  // namespace hcosim::models::deformable
