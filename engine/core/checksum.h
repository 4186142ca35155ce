#pragma once
#include <cstddef>
#include <cstdint>

namespace facesr {

// 64-bit FNV-1a. Used to detect corrupt files and to tie a trained model to
// the rig it was trained on; not a cryptographic hash.
uint64_t fnv1a64(const void* data, size_t size, uint64_t seed = 0xcbf29ce484222325ull);

}  // namespace facesr
