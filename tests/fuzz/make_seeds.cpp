// Writes the fuzzers' seed files (tiny_files.h) into a folder:
//   facesr_fuzz_seeds OUT_DIR [LIVELINK_DIR]
#include <cstdio>
#include <exception>

#include "tiny_files.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: facesr_fuzz_seeds OUT_DIR [LIVELINK_DIR]\n");
    return 2;
  }
  try {
    const auto files = facesr::tiny::write_seed_files(argv[1], argc > 2 ? argv[2] : "");
    std::printf("fuzz seeds: %zu files in %s\n", files.size(), argv[1]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "facesr_fuzz_seeds: %s\n", e.what());
    return 1;
  }
}
