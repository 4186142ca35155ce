#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/checksum.h"
#include "core/error.h"
#include "core/number_text.h"
#include "perf/sequence_format.h"
#include "perf/sequence_io.h"

namespace facesr {
namespace {

}  // namespace

SequenceWriter::SequenceWriter(const std::string& path, const SequenceHeader& header)
    : path_(path), tmp_(path + ".tmp." + std::to_string(::getpid())), header_(header) {
  header_.num_frames = 0;
  fsq::validate_header(header_, path_);
  file_.open(tmp_, std::ios::in | std::ios::out | std::ios::binary | std::ios::trunc);
  require(file_.is_open() && file_.good(),
          path_ + ": cannot create temporary file '" + tmp_ + "' (does the folder exist and is it writable?)");
  open_ = true;
  const std::vector<uint8_t> prefix = fsq::encode_prefix(header_, &frame_count_offset_);
  file_.write(reinterpret_cast<const char*>(prefix.data()), std::streamsize(prefix.size()));
  if (!file_.good()) fail("write to '" + tmp_ + "' failed (disk full?)");
  frame_buf_.resize(fsq::frame_bytes(header_));
}

SequenceWriter::~SequenceWriter() { abort(); }

void SequenceWriter::abort() noexcept {
  if (!open_) return;
  open_ = false;
  file_.close();
  std::remove(tmp_.c_str());
}

void SequenceWriter::fail(const std::string& problem) {
  abort();
  throw Error(path_ + ": " + problem);
}

void SequenceWriter::add_frame(double time, const float* nodes, const float* surface) {
  require(open_, path_ + ": sequence writer is closed (already committed, or aborted after an error)");
  const std::string where = "frame " + std::to_string(frames_) + ": ";
  if (!std::isfinite(time)) fail(where + "time is " + number_text(time) + " (must be finite)");
  if (frames_ > 0 && !(time > last_time_))
    fail(where + "time " + number_text(time) + " s is not after the previous frame's " + number_text(last_time_) +
         " s (times must be strictly increasing)");
  const uint64_t nn = header_.num_nodes * 3, ns = header_.num_surface * 3;
  if (nn > 0 && !nodes) fail(where + "node positions are missing (null)");
  if (ns > 0 && !surface) fail(where + "surface positions are missing (null)");
  if (const long i = nn ? fsq::first_non_finite(nodes, nn) : -1; i >= 0)
    fail(where + "node " + std::to_string(i / 3) + " has a non-finite coordinate (" + number_text(nodes[i]) + ")");
  if (const long i = ns ? fsq::first_non_finite(surface, ns) : -1; i >= 0)
    fail(where + "surface vertex " + std::to_string(i / 3) + " has a non-finite coordinate (" +
         number_text(surface[i]) + ")");

  // One write per frame: the stream buffers, but a frame is usually larger than its buffer.
  char* p = frame_buf_.data();
  std::memcpy(p, &time, sizeof time);
  if (nn) std::memcpy(p + sizeof time, nodes, nn * sizeof(float));
  if (ns) std::memcpy(p + sizeof time + nn * sizeof(float), surface, ns * sizeof(float));
  file_.write(p, std::streamsize(frame_buf_.size()));
  if (!file_.good()) fail("write to '" + tmp_ + "' failed (disk full?)");
  last_time_ = time;
  ++frames_;
}

void SequenceWriter::commit() {
  require(open_, path_ + ": sequence writer is closed (already committed, or aborted after an error)");
  if (frames_ == 0) fail("no frames were added (a sequence needs at least one frame)");
  file_.seekp(std::streamoff(frame_count_offset_));
  file_.write(reinterpret_cast<const char*>(&frames_), sizeof frames_);
  file_.flush();
  if (!file_.good()) fail("write to '" + tmp_ + "' failed (disk full?)");

  const uint64_t total = frame_count_offset_ + sizeof(uint64_t) + frames_ * fsq::frame_bytes(header_);
  file_.seekg(0);
  std::vector<char> chunk(std::size_t(1) << 20);
  uint64_t hash = fnv1a64(nullptr, 0), done = 0;
  while (done < total) {
    const auto n = std::streamsize(std::min<uint64_t>(chunk.size(), total - done));
    file_.read(chunk.data(), n);
    if (file_.gcount() != n) fail("re-reading '" + tmp_ + "' for its checksum failed");
    hash = fnv1a64(chunk.data(), std::size_t(n), hash);
    done += uint64_t(n);
  }
  file_.clear();
  file_.seekp(std::streamoff(total));
  file_.write(reinterpret_cast<const char*>(&hash), sizeof hash);
  file_.flush();
  if (!file_.good()) fail("write to '" + tmp_ + "' failed (disk full?)");
  file_.close();
  if (file_.fail()) fail("closing '" + tmp_ + "' failed (disk full?)");
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    open_ = true;  // so fail() removes the temporary file
    fail("cannot rename '" + tmp_ + "' to '" + path_ + "'");
  }
  open_ = false;
}

void write_sequence(const std::string& path, const Sequence& seq) {
  const SequenceHeader& h = seq.header;
  const uint64_t F = seq.time.size();
  require(seq.nodes.size() == F * h.num_nodes * 3 && seq.surface.size() == F * h.num_surface * 3,
          path + ": sequence arrays do not match the header (" + std::to_string(F) + " frames, " +
              std::to_string(h.num_nodes) + " nodes, " + std::to_string(h.num_surface) + " surface vertices)");
  SequenceWriter w(path, h);
  for (uint64_t f = 0; f < F; ++f)
    w.add_frame(seq.time[f], h.num_nodes ? seq.frame_nodes(int(f)) : nullptr,
                h.num_surface ? seq.frame_surface(int(f)) : nullptr);
  w.commit();
}

}  // namespace facesr
