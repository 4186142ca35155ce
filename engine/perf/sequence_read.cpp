#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/error.h"
#include "core/framed_file.h"
#include "perf/sequence_format.h"
#include "perf/sequence_io.h"

namespace facesr {
namespace {


std::string printable(const uint8_t* p, size_t n) {
  std::string s;
  for (size_t i = 0; i < n; ++i) s += std::isprint(p[i]) ? char(p[i]) : '?';
  return s;
}

}  // namespace

Sequence read_sequence(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  const size_t magic_size = fsq::kMagic.size();
  require(bytes.size() >= magic_size,
          path + ": truncated (" + std::to_string(bytes.size()) + " bytes, too short for a sequence file)");
  require(std::memcmp(bytes.data(), fsq::kMagic.data(), magic_size) == 0,
          path + ": not a facesr sequence file (bad magic '" + printable(bytes.data(), magic_size) +
              "', expected 'FACESRSQ')");

  ByteReader r(bytes.data(), bytes.size(), path);
  r.get<uint64_t>("magic");
  const auto version = r.get<uint32_t>("format version");
  require(version == fsq::kVersion, path + ": unsupported sequence format version " + std::to_string(version) +
                                        " (this build reads version " + std::to_string(fsq::kVersion) + ")");
  Sequence seq;
  SequenceHeader& h = seq.header;
  h.units = r.get_string("units");
  h.resolution = r.get_string("resolution");
  h.rig_checksum = r.get<uint64_t>("rig checksum");
  h.fps = r.get<double>("fps");
  h.num_nodes = r.get<uint64_t>("node count");
  h.num_surface = r.get<uint64_t>("surface vertex count");
  h.num_frames = r.get<uint64_t>("frame count");
  fsq::validate_header(h, path);

  const uint64_t per_frame = fsq::frame_bytes(h);
  check_framed_file(bytes, r.position(), h.num_frames, per_frame, path);

  const uint64_t F = h.num_frames, nn = h.num_nodes * 3, ns = h.num_surface * 3;
  seq.time.resize(F);
  seq.nodes.resize(F * nn);
  seq.surface.resize(F * ns);
  const uint8_t* p = bytes.data() + r.position();
  for (uint64_t f = 0; f < F; ++f, p += per_frame) {
    // The message is built only on failure: for frame 0 it would read
    // time[-1] (found by fuzzing), and for every good frame it cost a string.
    auto where = [&] { return path + ": frame " + std::to_string(f) + ": "; };
    double t;
    std::memcpy(&t, p, sizeof t);
    if (!std::isfinite(t)) throw Error(where() + "time is not finite");
    if (f > 0 && !(t > seq.time[f - 1]))
      throw Error(where() + "time " + std::to_string(t) + " s is not after the previous frame's " +
                  std::to_string(seq.time[f - 1]) + " s");
    seq.time[f] = t;
    float* nodes = seq.nodes.data() + f * nn;
    float* surface = seq.surface.data() + f * ns;
    if (nn) std::memcpy(nodes, p + sizeof t, nn * sizeof(float));
    if (ns) std::memcpy(surface, p + sizeof t + nn * sizeof(float), ns * sizeof(float));
    if (const long i = fsq::first_non_finite(nodes, nn); i >= 0)
      throw Error(where() + "node " + std::to_string(i / 3) + " has a non-finite coordinate");
    if (const long i = fsq::first_non_finite(surface, ns); i >= 0)
      throw Error(where() + "surface vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
  }
  return seq;
}

}  // namespace facesr
