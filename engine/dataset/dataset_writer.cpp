#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "core/checksum.h"
#include "core/error.h"
#include "dataset/dataset_format.h"
#include "dataset/dataset_io.h"

namespace facesr {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRestartHint = " (delete it, or restart the sequence, to discard it)";

}  // namespace

int DatasetSequence::weight_index(const std::string& name) const {
  for (size_t i = 0; i < header.weight_names.size(); ++i)
    if (header.weight_names[i] == name) return int(i);
  return -1;
}

DatasetWriter::DatasetWriter(const std::string& path, const DatasetHeader& header, bool restart)
    : path_(path), partial_(partial_path_for(path)), header_(header) {
  header_.num_frames = 0;
  fsd::validate_header(header_, path_);
  frame_buf_.resize(fsd::frame_bytes(header_) + sizeof(uint64_t));
  std::error_code ec;
  const bool exists = fs::exists(partial_, ec);
  if (exists && restart) {
    fs::remove(partial_, ec);
    require(!ec, partial_ + ": cannot remove the old partial file: " + ec.message());
  }
  if (exists && !restart)
    recover();
  else
    start_fresh();
}

DatasetWriter::~DatasetWriter() { close(); }

void DatasetWriter::close() noexcept {
  if (!file_) return;
  std::fclose(file_);
  file_ = nullptr;
}

void DatasetWriter::start_fresh() {
  file_ = std::fopen(partial_.c_str(), "wb");
  require(file_ != nullptr, path_ + ": cannot create '" + partial_ + "' (does the folder exist and is it writable?)");
  std::vector<uint8_t> prefix = fsd::encode_header(header_, fsd::kPartialMagic, false);
  const uint64_t hash = fnv1a64(prefix.data(), prefix.size());
  prefix.resize(prefix.size() + sizeof hash);
  std::memcpy(prefix.data() + prefix.size() - sizeof hash, &hash, sizeof hash);
  if (std::fwrite(prefix.data(), 1, prefix.size(), file_) != prefix.size() || std::fflush(file_) != 0) {
    close();
    throw Error(path_ + ": write to '" + partial_ + "' failed (disk full?)");
  }
  frames_ = recovered_ = 0;
}

// Keeps the verified frames of an existing partial file and cuts off the rest.
void DatasetWriter::recover() {
  uint64_t keep = 0;  // bytes of the partial file worth keeping
  std::string cut_reason;
  {
    fsd::FileReader r(partial_);
    std::array<char, 8> magic{};
    const uint64_t have = std::min<uint64_t>(r.size(), magic.size());
    r.read(magic.data(), have, "magic");
    require(std::memcmp(magic.data(), fsd::kPartialMagic.data(), have) == 0,
            partial_ + ": exists but is not a facesr dataset partial file" + kRestartHint);
    try {
      if (have < magic.size()) r.read(magic.data(), magic.size() - have, "magic");
      const auto version = r.get<uint32_t>("format version");
      require(version == fsd::kVersion, partial_ + ": was written by dataset format version " +
                                            std::to_string(version) + ", this build writes version " +
                                            std::to_string(fsd::kVersion) + kRestartHint);
      const DatasetHeader found = fsd::get_header(r, false);
      const uint64_t computed = r.hash(), stored = r.get<uint64_t>("header checksum");
      require(stored == computed, partial_ + ": header checksum mismatch (the file is corrupt)" +
                                      std::string(kRestartHint));
      const std::string diff = fsd::header_difference(found, header_);
      require(diff.empty(), partial_ + ": was started with a different header: " + diff +
                                " (in the file vs now)" + kRestartHint);
    } catch (const Error&) {
      // A header cut short: the writer died before its first frame, so there
      // is nothing to keep and nothing to lose.
      if (!r.truncated()) throw;
    }
    if (!r.truncated()) {
      keep = r.position();
      const uint64_t fb = fsd::frame_bytes(header_), record = fb + sizeof(uint64_t);
      DatasetFrame frame;
      while (r.remaining() >= record) {
        r.read(frame_buf_.data(), record, "frame");
        uint64_t stored;
        std::memcpy(&stored, frame_buf_.data() + fb, sizeof stored);
        if (stored != fnv1a64(frame_buf_.data(), fb)) {
          cut_reason = "frame " + std::to_string(frames_) + " fails its checksum";
          break;
        }
        fsd::decode_frame(header_, frame_buf_.data(), frame);
        try {
          fsd::validate_frame(header_, frame, "frame " + std::to_string(frames_), frames_ ? &last_time_ : nullptr);
        } catch (const Error& e) {
          cut_reason = e.what();
          break;
        }
        last_time_ = frame.time;
        ++frames_;
        keep = r.position();
      }
    }
    discarded_bytes_ = r.size() - keep;
  }
  recovered_ = frames_;
  if (keep == 0) {
    start_fresh();
    return;
  }
  if (discarded_bytes_ > 0) {
    std::error_code ec;
    fs::resize_file(partial_, keep, ec);
    require(!ec, partial_ + ": cannot cut off " + std::to_string(discarded_bytes_) + " damaged bytes after frame " +
                     std::to_string(frames_) + (cut_reason.empty() ? "" : " (" + cut_reason + ")") + ": " +
                     ec.message());
  }
  file_ = std::fopen(partial_.c_str(), "ab");
  require(file_ != nullptr, path_ + ": cannot reopen '" + partial_ + "' to append frames");
}

void DatasetWriter::add_frame(const DatasetFrame& frame) {
  require(file_ != nullptr, path_ + ": dataset writer is closed (already committed, or a write failed)");
  fsd::validate_frame(header_, frame, path_ + ": frame " + std::to_string(frames_), frames_ ? &last_time_ : nullptr);
  const uint64_t fb = fsd::frame_bytes(header_);
  fsd::encode_frame(header_, frame, frame_buf_.data());
  const uint64_t hash = fnv1a64(frame_buf_.data(), fb);
  std::memcpy(frame_buf_.data() + fb, &hash, sizeof hash);
  // Flushed to the OS after every frame, so killing the process can cost only
  // the frame being written; recovery verifies each frame's checksum anyway,
  // which also covers frames lost or damaged by a system crash.
  if (std::fwrite(frame_buf_.data(), 1, frame_buf_.size(), file_) != frame_buf_.size() || std::fflush(file_) != 0) {
    close();
    throw Error(path_ + ": write to '" + partial_ + "' failed (disk full?); the frames before frame " +
                std::to_string(frames_) + " are kept there for a later run");
  }
  last_time_ = frame.time;
  ++frames_;
}

void DatasetWriter::commit() {
  require(file_ != nullptr, path_ + ": dataset writer is closed (already committed, or a write failed)");
  require(frames_ > 0, path_ + ": no frames were added (a dataset sequence needs at least one frame)");
  // Closed first: whatever happens below, the partial file stays the resume point.
  const bool flushed = std::fflush(file_) == 0;
  close();
  require(flushed, path_ + ": write to '" + partial_ + "' failed (disk full?)");

  DatasetHeader final_header = header_;
  final_header.num_frames = frames_;
  const std::vector<uint8_t> prefix = fsd::encode_header(final_header, fsd::kMagic, true);
  const uint64_t partial_prefix = fsd::encode_header(header_, fsd::kPartialMagic, false).size() + sizeof(uint64_t);
  const uint64_t fb = fsd::frame_bytes(header_), record = fb + sizeof(uint64_t);

  std::ifstream in(partial_, std::ios::binary);
  require(in.good(), path_ + ": cannot reopen '" + partial_ + "' to finish the sequence");
  in.seekg(std::streamoff(partial_prefix));
  write_file_atomically(path_, [&](std::ostream& out) {
    uint64_t hash = fnv1a64(prefix.data(), prefix.size());
    out.write(reinterpret_cast<const char*>(prefix.data()), std::streamsize(prefix.size()));
    for (uint64_t f = 0; f < frames_; ++f) {
      in.read(reinterpret_cast<char*>(frame_buf_.data()), std::streamsize(record));
      require(uint64_t(in.gcount()) == record, path_ + ": '" + partial_ + "' ends before frame " + std::to_string(f));
      uint64_t stored;
      std::memcpy(&stored, frame_buf_.data() + fb, sizeof stored);
      // Re-checked because the frames spent time on disk since they were written.
      require(stored == fnv1a64(frame_buf_.data(), fb),
              path_ + ": frame " + std::to_string(f) + " in '" + partial_ + "' fails its checksum");
      hash = fnv1a64(frame_buf_.data(), fb, hash);
      out.write(reinterpret_cast<const char*>(frame_buf_.data()), std::streamsize(fb));
    }
    out.write(reinterpret_cast<const char*>(&hash), sizeof hash);
  });
  in.close();
  // A partial file left beside the finished one would be resumed by the next
  // writer for this path, so failing to remove it is an error, not a footnote.
  std::error_code ec;
  fs::remove(partial_, ec);
  require(!ec, path_ + ": is complete, but removing '" + partial_ + "' failed (" + ec.message() +
                   "); delete it by hand");
}

void write_dataset_sequence(const std::string& path, const DatasetSequence& seq) {
  DatasetWriter w(path, seq.header, /*restart=*/true);
  for (const DatasetFrame& f : seq.frames) w.add_frame(f);
  w.commit();
}

}  // namespace facesr
