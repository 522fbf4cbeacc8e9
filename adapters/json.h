// JSON, read and written with nlohmann-json: CLI output, bench and device
// reports, exports. Objects keep their keys in the order written (the
// IDL's field order); non-finite numbers are written as null (JSON has no
// NaN) and doubles as the shortest text that reads back to the same value.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace hcosim::adapters {

using Json = nlohmann::ordered_json;

// The double that `v`'s shortest decimal text reads as, so that 0.1f is
// written 0.1 and reads back as 0.1f (not 0.10000000149011612).
double json_float(float v);

// `j` on one line; invalid UTF-8 in a string is replaced, never thrown.
std::string json_line(const Json& j);

// The JSON document `text`; throws adapters::ConfigError "WHERE: not JSON:
// ..." with the parser's position.
Json parse_json(const std::string& text, const std::string& where);

}  // namespace hcosim::adapters
