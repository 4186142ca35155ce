#include <cctype>
#include <cstring>

#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/error.h"
#include "core/framed_file.h"
#include "dataset/dataset_format.h"
#include "dataset/dataset_io.h"

namespace facesr {
namespace {

std::string printable(const char* p, size_t n) {
  std::string s;
  for (size_t i = 0; i < n; ++i) s += std::isprint(static_cast<unsigned char>(p[i])) ? p[i] : '?';
  return s;
}

// Magic and version, from the first 12 bytes; says what the file is when it
// is not a finished dataset sequence.
void check_magic_and_version(const char* magic, uint64_t file_size, uint32_t version, const std::string& path) {
  const size_t n = fsd::kMagic.size();
  const std::string too_short =
      path + ": truncated (" + std::to_string(file_size) + " bytes, too short for a dataset file)";
  require(file_size >= n, too_short);
  require(std::memcmp(magic, fsd::kPartialMagic.data(), n) != 0,
          path + ": is an unfinished partial dataset file (the writer never committed it)");
  require(std::memcmp(magic, fsd::kMagic.data(), n) == 0,
          path + ": not a facesr dataset file (bad magic '" + printable(magic, n) + "', expected 'FACESRDS')");
  require(file_size >= n + sizeof version, too_short);
  require(version == fsd::kVersion, path + ": unsupported dataset format version " + std::to_string(version) +
                                        " (this build reads version " + std::to_string(fsd::kVersion) + ")");
}

}  // namespace

DatasetSequence read_dataset_sequence(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  uint32_t version = 0;
  if (bytes.size() >= 12) std::memcpy(&version, bytes.data() + 8, sizeof version);
  check_magic_and_version(reinterpret_cast<const char*>(bytes.data()), bytes.size(), version, path);

  ByteReader r(bytes.data(), bytes.size(), path);
  r.get<std::array<char, 8>>("magic");
  r.get<uint32_t>("format version");
  DatasetSequence seq;
  seq.header = fsd::get_header(r, true);
  const DatasetHeader& h = seq.header;
  fsd::validate_header(h, path);

  const uint64_t per_frame = fsd::frame_bytes(h);
  check_framed_file(bytes, r.position(), h.num_frames, per_frame, path);

  seq.frames.resize(h.num_frames);
  const uint8_t* p = bytes.data() + r.position();
  for (uint64_t f = 0; f < h.num_frames; ++f, p += per_frame) {
    fsd::decode_frame(h, p, seq.frames[f]);
    fsd::validate_frame(h, seq.frames[f], path + ": frame " + std::to_string(f), f ? &seq.frames[f - 1].time : nullptr);
  }
  return seq;
}

DatasetHeader read_dataset_header(const std::string& path) {
  fsd::FileReader r(path);
  std::array<char, 8> magic{};
  const uint64_t have = std::min<uint64_t>(r.size(), magic.size());
  r.read(magic.data(), have, "magic");
  const uint32_t version = r.remaining() >= 4 ? r.get<uint32_t>("format version") : 0;
  check_magic_and_version(magic.data(), r.size(), version, path);
  DatasetHeader h = fsd::get_header(r, true);
  fsd::validate_header(h, path);
  require(h.num_frames >= 1, path + ": has no frames");
  return h;
}

}  // namespace facesr
