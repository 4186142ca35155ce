#pragma once
// One entry point per file loader a user can hand facesr. Each takes the
// raw bytes of a file, writes them where the loader reads them and loads:
// a facesr::Error is the expected answer to a bad file, any other exception
// or a crash is a bug. Shared by the libFuzzer executables (tests/fuzz,
// scripts/fuzz.sh) and the GoogleTest that replays seeds and the inputs
// fuzzing once broke (tests/test_fuzz_targets.cpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace facesr::fuzz {

enum class Outcome { Accepted, Rejected };

struct Target {
  const char* name;       // "rig", ... : the executable is fuzz_<name>
  const char* extension;  // of the files it reads: ".rig", ...
  Outcome (*run)(const uint8_t* data, size_t size);
};

// Every target, in a fixed order.
const std::vector<Target>& targets();
// The target with this name; nullptr if none.
const Target* find_target(const std::string& name);

// Binary formats end in an FNV-1a 64 checksum, so almost every mutated file
// would stop at the checksum test. The binary targets therefore load each
// input twice: as given (the checksum and size checks), and resealed (the
// size fields and checksum made to match) so mutations reach the parsers
// behind the checksum.
std::vector<uint8_t> reseal_trailing_checksum(const uint8_t* data, size_t size);  // .fsm .fsq .fsd
std::vector<uint8_t> reseal_rig(const uint8_t* data, size_t size);                // .rig

// The blendshape names the performance loaders are given: the ICT FaceKit's
// 53 (so Live Link columns map as they do on a real head).
const std::vector<std::string>& rig_names();

}  // namespace facesr::fuzz
