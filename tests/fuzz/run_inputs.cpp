// tests/fuzz/run_inputs.cpp - the driver of a fuzz target outside libFuzzer: runs
// LLVMFuzzerTestOneInput once on every file named on the command line (directories: every
// file in them, in name order). The ordinary test suite runs each target this way over its
// committed corpus (tests/fuzz/corpus/<target>), whose files include every input that ever
// found a bug, so a regression fails in every build, not only under the fuzzer.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size);

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    fs::path const p(argv[i]);
    if (fs::is_directory(p)) {
      for (auto const& e : fs::directory_iterator(p))
        if (e.is_regular_file()) files.push_back(e.path());
    } else if (fs::exists(p)) {
      files.push_back(p);
    } else {
      std::fprintf(stderr, "run_inputs: %s does not exist\n", argv[i]);
      return 2;
    }
  }
  std::sort(files.begin(), files.end());
  for (auto const& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::vector<std::uint8_t> const bytes{std::istreambuf_iterator<char>(in), {}};
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  }
  std::printf("run_inputs: %zu inputs, every property held\n", files.size());
  return files.empty() ? 1 : 0;
}
