#include "adapters/json.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "adapters/config.h"

namespace hcosim::adapters {

double json_float(float v) {
  if (!std::isfinite(v)) return v;
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text - 1, v).ptr;
  *end = '\0';
  return std::strtod(text, nullptr);
}

std::string json_line(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

Json parse_json(const std::string& text, const std::string& where) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw ConfigError(where + ": not JSON: " + e.what());
  }
}

}  // namespace hcosim::adapters
