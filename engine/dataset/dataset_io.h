#pragma once
#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

// Paired LR/HR dataset sequence (".fsd"), version 1: for one performance,
// per frame the controls (blendshape weights, jaw transform), the LR lattice
// displacement, the HR face-surface displacement, the face surface the LR
// lattice carries through its barycentric embedding, and the solve
// statistics. This is what the super-resolution network trains on: input the
// embedded (LR) surface, target the HR surface.
// All integers and floats little-endian; strings are u64 length + bytes.
//
//   offset  size  field
//   0       8     magic "FACESRDS"
//   8       4     u32 format version (= 1)
//   12            header:
//                   string units          "cm" (every length is in centimetres)
//                   string name           performance name, non-empty
//                   u64    rig checksum   (rig_checksum() of the rig simulated)
//                   f64    fps            in (0, 1000]
//                   u64    LR node count N          >= 1
//                   u64    surface vertex count S   >= 1 (HR face surface = rig surface)
//                   u64    weight count B           >= 0
//                   B × string weight names (blendshape names in weight order,
//                          non-empty, distinct)
//                   u64    frame count F            >= 1
//   H             F frames, each 8 + 4 B + 48 + 12 N + 24 S + 52 bytes:
//                   f64    time (s), strictly increasing
//                   f32    weights, B
//                   f32    jaw, 12: rotation R row-major (9) then translation
//                          t (3, cm); the rigid jaw transform x' = R x + t
//                   f32    lr_disp, N × 3: LR node displacement from the LR rest pose
//                   f32    hr_disp, S × 3: HR face-surface vertex displacement
//                          from the HR rest surface
//                   f32    embedded_disp, S × 3: the face surface carried by the
//                          LR embedding, displacement from the LR rest surface
//                   stats, 52 bytes:
//                     f64 hr_step_s, f64 lr_step_ms,
//                     f32 max_penetration_cm, f32 max_penetration_free_cm,
//                     i32 contacts, i32 hr_newton_iters, i32 hr_cg_iters,
//                     i32 lr_newton_iters, i32 lr_cg_iters,
//                     f32 hr_rel_residual, f32 lr_rel_residual
//   H + F*(...)   u64 FNV-1a 64 of every byte before it (from offset 0)
//
// Nothing may follow the checksum. Every float is finite. The stats are
// either >= 0 or exactly -1 ("not measured"); max_penetration_free_cm is the
// same measurement on a collision-free solve when one was run. Any change to
// this layout needs a new format version.
//
// While a sequence is being written it lives in "<path>.partial", a
// different layout built so that every frame can be verified on its own and a
// killed run can resume where it stopped:
//
//   0       8     magic "FACESRDP"
//   8       4     u32 format version (= 1)
//   12            the header above, without the frame count
//   P             u64 FNV-1a 64 of bytes [0, P)
//   P + 8         frames, each the frame bytes above followed by a u64
//                 FNV-1a 64 of those frame bytes
//
// A partial file has no frame count and no end marker: it ends after its
// last complete frame, or in the middle of the frame being written when the
// writer was killed.

namespace facesr {

struct DatasetHeader {
  std::string units = "cm";
  std::string name;  // performance name
  uint64_t rig_checksum = 0;
  double fps = 30;
  uint64_t num_lr_nodes = 0, num_surface = 0;
  std::vector<std::string> weight_names;
  uint64_t num_frames = 0;  // ignored by DatasetWriter, which counts the frames it is given
};

// Solve statistics of one frame; -1 in any field means "not measured".
struct DatasetFrameStats {
  double hr_step_s = 0, lr_step_ms = 0;
  float max_penetration_cm = 0;        // with collision handling
  float max_penetration_free_cm = -1;  // the same on a collision-free solve, if one was run
  int32_t contacts = 0, hr_newton_iters = 0, hr_cg_iters = 0, lr_newton_iters = 0, lr_cg_iters = 0;
  float hr_rel_residual = 0, lr_rel_residual = 0;
};

struct DatasetFrame {
  double time = 0;                  // s
  std::vector<float> weights;       // B
  std::array<float, 12> jaw{};      // R row-major, then t (cm)
  std::vector<float> lr_disp;       // N × 3, cm
  std::vector<float> hr_disp;       // S × 3, cm
  std::vector<float> embedded_disp; // S × 3, cm
  DatasetFrameStats stats;
};

struct DatasetSequence {
  DatasetHeader header;
  std::vector<DatasetFrame> frames;

  int num_frames() const { return int(frames.size()); }
  const DatasetFrame& frame(int f) const { return frames.at(size_t(f)); }
  double duration_s() const { return frames.empty() ? 0 : frames.back().time - frames.front().time; }
  // Index of a blendshape weight by name, or -1.
  int weight_index(const std::string& name) const;
};

// Streams frames to "<path>.partial", flushing after every frame so that a
// killed process loses at most the frame it was writing; commit() writes the
// finished file at `path` (through a temporary name and a rename) and
// removes the partial file.
//
// Resuming: when "<path>.partial" already exists with the same header (every
// field but the frame count), the constructor keeps each frame in it that is
// complete, matches its checksum and is valid, and cuts the file after the
// last such frame (a frame cut short by a kill, and anything after a damaged
// frame, is discarded); frames() then says how many were recovered and the
// caller continues from there. A partial file with another header, or one
// that is not a dataset partial file, is an Error naming the difference
// unless `restart` is set, in which case it is discarded.
//
// Unlike SequenceWriter, destroying the writer without commit() keeps the
// partial file: it is the resume point. An invalid frame (wrong size,
// non-finite value, time not increasing) is rejected before anything is
// written, and the writer stays usable; a failed write closes the writer
// (the partial file stays, and the next run cuts the half frame off).
// Two writers must not work on the same path at once.
class DatasetWriter {
 public:
  DatasetWriter(const std::string& path, const DatasetHeader& header, bool restart = false);
  ~DatasetWriter();
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  void add_frame(const DatasetFrame& frame);
  // Needs at least one frame. Replaces any file already at `path`.
  void commit();

  uint64_t frames() const { return frames_; }
  // Frames found in the partial file when the writer was opened.
  uint64_t recovered_frames() const { return recovered_; }
  // Bytes of the partial file cut off when it was opened (a half-written frame).
  uint64_t discarded_bytes() const { return discarded_bytes_; }
  // Time of the last frame written or recovered (meaningless while frames() == 0).
  double last_time() const { return last_time_; }
  const std::string& path() const { return path_; }
  const std::string& partial_path() const { return partial_; }
  static std::string partial_path_for(const std::string& path) { return path + ".partial"; }

 private:
  void recover();
  void start_fresh();
  void close() noexcept;

  std::string path_, partial_;
  DatasetHeader header_;
  std::FILE* file_ = nullptr;
  uint64_t frames_ = 0, recovered_ = 0, discarded_bytes_ = 0;
  double last_time_ = 0;
  std::vector<uint8_t> frame_buf_;
};

// Reads and validates a dataset sequence: magic, version, header values,
// sizes (truncated or trailing bytes), checksum, frame values and increasing
// times. Every Error names `path` and the problem.
DatasetSequence read_dataset_sequence(const std::string& path);

// Reads only the header (with the frame count), without the frames or the
// checksum: cheap, for listing a dataset.
DatasetHeader read_dataset_header(const std::string& path);

// Convenience: writes a whole in-memory sequence through a fresh
// DatasetWriter (discarding any partial file at the path).
void write_dataset_sequence(const std::string& path, const DatasetSequence& seq);

}  // namespace facesr
