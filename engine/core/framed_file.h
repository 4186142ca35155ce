#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace facesr {

// Size and integrity checks shared by the engine's frame-sequence formats
// (.fsq, .fsd): a header ending at `header_end`, then `num_frames` frames of
// `frame_bytes` each, then a u64 FNV-1a 64 of every byte before it. Sizes are
// checked before the checksum, so a cut-off file is reported as truncated
// rather than as corrupt. Errors name `path`.
void check_framed_file(const std::vector<uint8_t>& bytes, uint64_t header_end, uint64_t num_frames,
                       uint64_t frame_bytes, const std::string& path);

std::string hex64(uint64_t v);  // "0x0123456789abcdef"

}  // namespace facesr
