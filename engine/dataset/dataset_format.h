#pragma once
#include <array>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "dataset/dataset_io.h"

// Pieces of the .fsd layout and of its partial file (see dataset_io.h) shared
// by the writer and the reader, so the two cannot drift apart.
namespace facesr::fsd {

constexpr std::array<char, 8> kMagic = {'F', 'A', 'C', 'E', 'S', 'R', 'D', 'S'};
constexpr std::array<char, 8> kPartialMagic = {'F', 'A', 'C', 'E', 'S', 'R', 'D', 'P'};
constexpr uint32_t kVersion = 1;
constexpr uint64_t kMaxCount = 1ull << 28;    // LR nodes or surface vertices: far above any rig
constexpr uint64_t kMaxWeights = 1ull << 16;  // blendshapes: ARKit has 52
constexpr double kMaxFps = 1000;
constexpr uint64_t kStatsBytes = 2 * 8 + 2 * 4 + 5 * 4 + 2 * 4;

// Throws Error "<context>: ..." for units other than cm, an empty name, fps
// outside (0, 1000], counts out of range, or empty or repeated weight names.
void validate_header(const DatasetHeader& h, const std::string& context);

// "" when a and b agree in every field but the frame count, else the first
// difference, e.g. "rig checksum 0x... vs 0x...".
std::string header_difference(const DatasetHeader& a, const DatasetHeader& b);

// Magic, version and header. The final file carries the frame count
// (*frame_count_offset receives its byte offset); the partial file does not.
std::vector<uint8_t> encode_header(const DatasetHeader& h, const std::array<char, 8>& magic, bool with_frame_count,
                                   uint64_t* frame_count_offset = nullptr);

// Header fields after magic and version, from anything with ByteReader's
// get<T>(what), get_string(what) and source().
template <class Reader>
DatasetHeader get_header(Reader& r, bool with_frame_count) {
  DatasetHeader h;
  h.units = r.get_string("units");
  h.name = r.get_string("name");
  h.rig_checksum = r.template get<uint64_t>("rig checksum");
  h.fps = r.template get<double>("fps");
  h.num_lr_nodes = r.template get<uint64_t>("LR node count");
  h.num_surface = r.template get<uint64_t>("surface vertex count");
  const auto B = r.template get<uint64_t>("weight count");
  require(B <= kMaxWeights, r.source() + ": weight count " + std::to_string(B) + " is implausible");
  h.weight_names.reserve(B);
  for (uint64_t i = 0; i < B; ++i) h.weight_names.push_back(r.get_string("weight name"));
  if (with_frame_count) h.num_frames = r.template get<uint64_t>("frame count");
  return h;
}

// Bytes of one frame (without the partial file's per-frame checksum).
inline uint64_t frame_bytes(const DatasetHeader& h) {
  return sizeof(double) + 4 * (h.weight_names.size() + 12 + 3 * h.num_lr_nodes + 6 * h.num_surface) + kStatsBytes;
}

// Throws Error "<where>: ..." when the frame's arrays do not match the header,
// a value is not finite, a stat is neither >= 0 nor -1, or the time does not
// follow *previous_time (when given).
void validate_frame(const DatasetHeader& h, const DatasetFrame& f, const std::string& where,
                    const double* previous_time);

// frame_bytes(h) bytes. encode_frame expects a validated frame.
void encode_frame(const DatasetHeader& h, const DatasetFrame& f, uint8_t* out);
void decode_frame(const DatasetHeader& h, const uint8_t* in, DatasetFrame& f);

// Sequential reader of a file on disk with ByteReader's interface, hashing
// (FNV-1a 64) what it reads, so the partial file can be checked while it is
// streamed instead of being held in memory.
class FileReader {
 public:
  explicit FileReader(const std::string& path);
  template <class T>
  T get(const char* what) {
    T v;
    read(&v, sizeof v, what);
    return v;
  }
  std::string get_string(const char* what);
  void read(void* out, uint64_t n, const char* what);
  uint64_t position() const { return pos_; }
  uint64_t size() const { return size_; }
  uint64_t remaining() const { return size_ - pos_; }
  uint64_t hash() const { return hash_; }
  bool truncated() const { return truncated_; }  // a read ran past the end
  const std::string& source() const { return path_; }

 private:
  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0, pos_ = 0, hash_;
  bool truncated_ = false;
};

std::string hex(uint64_t v);

}  // namespace facesr::fsd
