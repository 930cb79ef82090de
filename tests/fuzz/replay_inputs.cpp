// Replays files through the fuzz entry point without libFuzzer, so that the
// regression files and the seed corpus run in every build (ctest
// fuzz_regressions). Arguments: files or directories (read non-recursively,
// in name order). Fails if no file was found; a bad input aborts the process.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/read_file.h"
#include "io/scene_error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

std::vector<std::filesystem::path> inputs(int argc, char** argv) {
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) {
    std::filesystem::path arg = argv[i];
    if (!std::filesystem::is_directory(arg)) {
      files.push_back(arg);
      continue;
    }
    std::vector<std::filesystem::path> in_dir;
    for (const auto& entry : std::filesystem::directory_iterator(arg))
      if (entry.is_regular_file() && entry.path().filename().string().front() != '.') in_dir.push_back(entry.path());
    std::sort(in_dir.begin(), in_dir.end());
    files.insert(files.end(), in_dir.begin(), in_dir.end());
  }
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::filesystem::path> files = inputs(argc, argv);
  if (files.empty()) {
    std::fprintf(stderr, "replay_fuzz_inputs: no input files given\n");
    return 1;
  }
  for (const std::filesystem::path& f : files) {
    std::string bytes;
    try {
      bytes = pt::read_regular_file(f, "fuzz input", uint64_t(1) << 30);
    } catch (const pt::InputError& e) {
      std::fprintf(stderr, "replay_fuzz_inputs: %s\n", e.what());
      return 1;
    }
    std::fprintf(stderr, "%s (%zu bytes)\n", f.c_str(), bytes.size());
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  }
  std::printf("replay_fuzz_inputs: %zu inputs loaded or rejected cleanly\n", files.size());
  return 0;
}
