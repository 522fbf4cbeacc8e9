// Shared by the libFuzzer targets: the parsers under test read files, so
// each input is written to a scratch file first; a refusal must be an
// exception with a message, anything else (a crash, a sanitizer report, a
// hang, an allocation over libFuzzer's limit) is a finding.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>

namespace hcosim::fuzz {

// A file holding `data`, rewritten for every input; `ext` for parsers that
// go by the name (OpenCV's FileStorage).
// Removed when the fuzzer exits.
inline std::string scratch(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  static const struct File {
    std::string path;
    ~File() { std::remove(path.c_str()); }
  } file{"/tmp/hcosim_fuzz_" + std::to_string(getpid()) + ext};
  std::ofstream(file.path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return file.path;
}

// Runs `parse`; an exception is a refusal and must say what was wrong.
template <class F>
int refuse_or_accept(F&& parse) {
  try {
    parse();
  } catch (const std::exception& e) {
    if (std::string(e.what()).empty()) {
      std::fprintf(stderr, "refused with an empty message\n");
      std::abort();
    }
  }
  return 0;
}

}  // namespace hcosim::fuzz
