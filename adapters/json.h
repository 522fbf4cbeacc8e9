// Compact JSON text builder: CLI output, bench reports, recordings.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hcosim::adapters {

// Appends JSON tokens to a string, placing commas itself. Non-finite
// numbers become null (JSON has no NaN); doubles use the shortest text that
// reads back to the same value.
class Json {
 public:
  Json& begin_object();
  Json& end_object();
  Json& begin_array();
  Json& end_array();
  Json& key(std::string_view k);
  Json& value(double v);
  Json& value(float v);
  Json& value(std::int64_t v);
  Json& value(std::uint64_t v);
  Json& value(int v) { return value(static_cast<std::int64_t>(v)); }
  Json& value(unsigned v) { return value(static_cast<std::uint64_t>(v)); }
  Json& value(bool v);
  Json& value(std::string_view v);
  Json& value(const char* v) { return value(std::string_view(v)); }
  Json& null();

  const std::string& str() const { return out_; }

 private:
  void separate();
  Json& open(char bracket);
  Json& close(char bracket);
  template <class F>
  Json& number(F v);
  std::string out_;
  std::vector<bool> first_;  // one entry per open container: no element yet
  bool after_key_ = false;
};

}  // namespace hcosim::adapters
