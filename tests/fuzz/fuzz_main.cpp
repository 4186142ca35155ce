// libFuzzer entry point of one target, chosen at compile time
// (FACESR_FUZZ_TARGET, e.g. "rig"): fuzz_<target> in scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_targets.h"

static const facesr::fuzz::Target* target() {
  static const facesr::fuzz::Target* t = [] {
    const auto* found = facesr::fuzz::find_target(FACESR_FUZZ_TARGET);
    if (!found) {
      std::fprintf(stderr, "fuzz: no target named '%s'\n", FACESR_FUZZ_TARGET);
      std::abort();
    }
    return found;
  }();
  return t;
}

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, size_t size) {
  (void)target()->run(data, size);
  return 0;
}
