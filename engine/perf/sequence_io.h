#pragma once
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

// Simulated sequence file (".fsq"), version 1: the per-frame node positions of
// one simulation mesh (LR lattice or HR mesh) and the face surface they carry.
// All integers and floats little-endian; strings are u64 length + bytes.
//
//   offset  size  field
//   0       8     magic "FACESRSQ"
//   8       4     u32 format version (= 1)
//   12            header:
//                   string units        "cm" (positions are in centimetres)
//                   string resolution   "low" (LR lattice) or "high" (HR mesh)
//                   u64    rig checksum (rig_checksum() of the rig simulated)
//                   f64    fps          in (0, 1000]
//                   u64    node count N
//                   u64    surface vertex count S
//                   u64    frame count F
//   H             F frames, each 8 + 12 N + 12 S bytes:
//                   f64    time (s), finite, strictly increasing
//                   f32    node positions, N × 3 (x, y, z per node)
//                   f32    surface positions, S × 3
//   H + F*(...)   u64 FNV-1a 64 of every byte before it (from offset 0)
//
// Nothing may follow the checksum. N may be 0 (a surface-only sequence) but
// N + S > 0. Every coordinate is finite. Any change to this layout needs a new
// format version.

namespace facesr {

struct SequenceHeader {
  std::string units = "cm";
  std::string resolution = "low";  // "low" | "high"
  uint64_t rig_checksum = 0;
  double fps = 30;
  uint64_t num_nodes = 0;
  uint64_t num_surface = 0;
  uint64_t num_frames = 0;  // ignored by SequenceWriter, which counts the frames it is given
};

struct Sequence {
  SequenceHeader header;
  std::vector<double> time;    // per frame, seconds
  std::vector<float> nodes;    // frames × N × 3, cm
  std::vector<float> surface;  // frames × S × 3, cm

  int frames() const { return int(time.size()); }
  const float* frame_nodes(int f) const { return nodes.data() + size_t(f) * header.num_nodes * 3; }
  const float* frame_surface(int f) const { return surface.data() + size_t(f) * header.num_surface * 3; }
};

// Streams frames to "<path>.tmp.<pid>" so a long run never holds them all in
// memory; commit() fills in the frame count and checksum and renames the file
// into place. Until then nothing exists at `path`. If the writer is destroyed
// without commit(), or any call throws (a non-finite coordinate, a time that
// does not increase, a failed write), the temporary file is removed, so no
// partial file is ever left; later calls then throw.
class SequenceWriter {
 public:
  SequenceWriter(const std::string& path, const SequenceHeader& header);
  ~SequenceWriter();
  SequenceWriter(const SequenceWriter&) = delete;
  SequenceWriter& operator=(const SequenceWriter&) = delete;

  // nodes: N × 3 floats (may be null when N = 0); surface: S × 3 floats (cm).
  void add_frame(double time, const float* nodes, const float* surface);
  // Needs at least one frame. Re-reads the temporary file once to checksum it,
  // because the frame count, known only now, precedes the frames.
  void commit();

  uint64_t frames() const { return frames_; }
  const std::string& path() const { return path_; }

 private:
  void abort() noexcept;
  [[noreturn]] void fail(const std::string& problem);

  std::string path_, tmp_;
  SequenceHeader header_;
  std::fstream file_;
  uint64_t frame_count_offset_ = 0;
  uint64_t frames_ = 0;
  double last_time_ = 0;
  bool open_ = false;
  std::vector<char> frame_buf_;
};

// Reads and validates a sequence file: magic, version, header values, sizes
// (truncated or trailing bytes), checksum, finite coordinates and increasing
// times. Every Error names `path` and the problem.
Sequence read_sequence(const std::string& path);

// Convenience: writes a whole in-memory sequence through SequenceWriter.
void write_sequence(const std::string& path, const Sequence& seq);

}  // namespace facesr
