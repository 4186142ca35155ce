#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "perf/sequence_io.h"

// Pieces of the .fsq layout (see sequence_io.h) shared by the writer and the
// reader, so the two cannot drift apart.
namespace facesr::fsq {

constexpr std::array<char, 8> kMagic = {'F', 'A', 'C', 'E', 'S', 'R', 'S', 'Q'};
constexpr uint32_t kVersion = 1;
constexpr uint64_t kMaxCount = 1ull << 28;  // nodes or surface vertices: far above any rig
constexpr double kMaxFps = 1000;

// Throws Error "<context>: ..." for units other than cm, an unknown
// resolution, fps outside (0, 1000], or implausible counts.
void validate_header(const SequenceHeader& h, const std::string& context);

// Magic, version and header; *frame_count_offset receives the byte offset of
// the frame count so the writer can patch it.
std::vector<uint8_t> encode_prefix(const SequenceHeader& h, uint64_t* frame_count_offset);

// Bytes per frame: time, nodes, surface.
inline uint64_t frame_bytes(const SequenceHeader& h) {
  return sizeof(double) + 3 * sizeof(float) * (h.num_nodes + h.num_surface);
}

// Index of the first non-finite value among n floats, or -1.
long first_non_finite(const float* v, uint64_t n);

}  // namespace facesr::fsq
