#include "core/framed_file.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "core/checksum.h"
#include "core/error.h"

namespace facesr {

std::string hex64(uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%016" PRIx64, v);
  return buf;
}

void check_framed_file(const std::vector<uint8_t>& bytes, uint64_t header_end, uint64_t num_frames,
                       uint64_t frame_bytes, const std::string& path) {
  const uint64_t available = bytes.size() > header_end ? bytes.size() - header_end : 0;
  const uint64_t frames_fit = available >= 8 ? (available - 8) / frame_bytes : 0;
  require(num_frames >= 1, path + ": has no frames");
  require(num_frames <= frames_fit, path + ": truncated: the header promises " + std::to_string(num_frames) +
                                        " frames of " + std::to_string(frame_bytes) + " bytes, but only " +
                                        std::to_string(frames_fit) + " fit in the file's " +
                                        std::to_string(bytes.size()) + " bytes");
  const uint64_t expected = header_end + num_frames * frame_bytes + 8;
  require(bytes.size() == expected, path + ": " + std::to_string(bytes.size() - expected) +
                                        " unexpected bytes after the checksum (trailing data: the file has " +
                                        std::to_string(bytes.size()) + ", expected " + std::to_string(expected) + ")");
  uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  const uint64_t computed = fnv1a64(bytes.data(), bytes.size() - 8);
  require(stored == computed, path + ": checksum mismatch (stored " + hex64(stored) + ", computed " +
                                  hex64(computed) + "): the file is corrupt");
}

}  // namespace facesr
