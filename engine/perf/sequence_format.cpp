#include "perf/sequence_format.h"

#include <cmath>

#include "core/binary_io.h"
#include "core/error.h"

namespace facesr::fsq {

void validate_header(const SequenceHeader& h, const std::string& context) {
  require(h.units == "cm", context + ": units are '" + h.units + "', expected 'cm'");
  require(h.resolution == "low" || h.resolution == "high",
          context + ": resolution is '" + h.resolution + "', expected 'low' or 'high'");
  require(std::isfinite(h.fps) && h.fps > 0 && h.fps <= kMaxFps,
          context + ": fps " + std::to_string(h.fps) + " is not in (0, 1000]");
  require(h.num_nodes <= kMaxCount, context + ": node count " + std::to_string(h.num_nodes) + " is implausible");
  require(h.num_surface <= kMaxCount,
          context + ": surface vertex count " + std::to_string(h.num_surface) + " is implausible");
  require(h.num_nodes + h.num_surface > 0, context + ": has neither nodes nor surface vertices");
}

std::vector<uint8_t> encode_prefix(const SequenceHeader& h, uint64_t* frame_count_offset) {
  ByteWriter w;
  w.put(kMagic);
  w.put<uint32_t>(kVersion);
  w.put_string(h.units);
  w.put_string(h.resolution);
  w.put<uint64_t>(h.rig_checksum);
  w.put<double>(h.fps);
  w.put<uint64_t>(h.num_nodes);
  w.put<uint64_t>(h.num_surface);
  if (frame_count_offset) *frame_count_offset = w.bytes().size();
  w.put<uint64_t>(h.num_frames);
  return std::move(w.bytes());
}

long first_non_finite(const float* v, uint64_t n) {
  for (uint64_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return long(i);
  return -1;
}

}  // namespace facesr::fsq
