// A fresh folder for one test's files, named after the test and the process
// (ctest runs tests in parallel), removed when it goes out of scope.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace hcosim::tests {

struct TempDir {
  std::filesystem::path path;
  TempDir() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    path = std::filesystem::temp_directory_path() /
           ("hcosim_" + std::string(test->test_suite_name()) + "_" + test->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  // The path of `name` in the folder, written with `text` unless it is empty.
  std::string file(const std::string& name, const std::string& text = "") const {
    const std::filesystem::path p = path / name;
    if (!text.empty()) std::ofstream(p) << text;
    return p.string();
  }
};

// The message of the E that `f` throws; "" when it throws none.
template <class E = std::exception, class F>
std::string message_of(F f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

}  // namespace hcosim::tests
