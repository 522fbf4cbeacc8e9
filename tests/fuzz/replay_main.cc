// Runs a fuzz target's LLVMFuzzerTestOneInput over files and folders
// without libFuzzer: any compiler's build replays the seed corpora and
// every input that once crashed (ctest fuzz.replay_*).
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::size_t inputs = 0;
  const auto run = [&](const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    ++inputs;
  };
  for (int k = 1; k < argc; ++k) {
    if (!fs::exists(argv[k])) {
      std::cerr << argv[k] << ": no such file or folder\n";
      return 2;
    }
    if (fs::is_directory(argv[k])) {
      for (const auto& e : fs::recursive_directory_iterator(argv[k]))
        if (e.is_regular_file()) run(e.path());
    } else {
      run(argv[k]);
    }
  }
  std::cout << inputs << " inputs replayed, none crashed\n";
  return inputs > 0 ? 0 : 1;
}
