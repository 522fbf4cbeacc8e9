// Little-endian values in byte strings, as hcosim's recordings and MCAP
// files lay them out. Every machine hcosim builds for is little-endian, so
// a value's bytes are copied as they are.
#pragma once

#include <cstring>
#include <string>
#include <type_traits>

namespace hcosim::services::recording {

// Appends v's bytes to out.
template <class U>
void append_le(std::string& out, U v) {
  static_assert(std::is_arithmetic_v<U>, "a number");
  char b[sizeof(U)];
  std::memcpy(b, &v, sizeof(U));
  out.append(b, sizeof(U));
}

// Reads a U at p and moves p past it. Precondition: sizeof(U) bytes at p.
template <class U>
U read_le(const char*& p) {
  static_assert(std::is_arithmetic_v<U>, "a number");
  U v;
  std::memcpy(&v, p, sizeof(U));
  p += sizeof(U);
  return v;
}

}  // namespace hcosim::services::recording
