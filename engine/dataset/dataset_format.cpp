#include "dataset/dataset_format.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <set>

#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/number_text.h"

namespace facesr::fsd {
namespace {

// Index of the first non-finite value, or -1.
long first_non_finite(const std::vector<float>& v) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return long(i);
  return -1;
}

template <class T>
void put(uint8_t*& p, const T& v) {
  std::memcpy(p, &v, sizeof v);
  p += sizeof v;
}
void put_floats(uint8_t*& p, const float* v, size_t n) {
  if (n) std::memcpy(p, v, n * sizeof(float));
  p += n * sizeof(float);
}
template <class T>
void take(const uint8_t*& p, T& v) {
  std::memcpy(&v, p, sizeof v);
  p += sizeof v;
}
void take_floats(const uint8_t*& p, float* v, size_t n) {
  if (n) std::memcpy(v, p, n * sizeof(float));
  p += n * sizeof(float);
}

}  // namespace

std::string hex(uint64_t v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%016llx", static_cast<unsigned long long>(v));
  return buf;
}

void validate_header(const DatasetHeader& h, const std::string& context) {
  require(h.units == "cm", context + ": units are '" + h.units + "', expected 'cm'");
  require(!h.name.empty(), context + ": the performance name is empty");
  require(std::isfinite(h.fps) && h.fps > 0 && h.fps <= kMaxFps,
          context + ": fps " + number_text(h.fps) + " is not in (0, 1000]");
  require(h.num_lr_nodes >= 1 && h.num_lr_nodes <= kMaxCount,
          context + ": LR node count " + std::to_string(h.num_lr_nodes) + " is not in [1, 2^28]");
  require(h.num_surface >= 1 && h.num_surface <= kMaxCount,
          context + ": surface vertex count " + std::to_string(h.num_surface) + " is not in [1, 2^28]");
  require(h.weight_names.size() <= kMaxWeights,
          context + ": " + std::to_string(h.weight_names.size()) + " weight names, at most 65536");
  std::set<std::string> seen;
  for (size_t i = 0; i < h.weight_names.size(); ++i) {
    require(!h.weight_names[i].empty(), context + ": weight name " + std::to_string(i) + " is empty");
    require(seen.insert(h.weight_names[i]).second,
            context + ": weight name '" + h.weight_names[i] + "' appears twice");
  }
}

std::string header_difference(const DatasetHeader& a, const DatasetHeader& b) {
  if (a.units != b.units) return "units '" + a.units + "' vs '" + b.units + "'";
  if (a.name != b.name) return "performance name '" + a.name + "' vs '" + b.name + "'";
  if (a.rig_checksum != b.rig_checksum) return "rig checksum " + hex(a.rig_checksum) + " vs " + hex(b.rig_checksum);
  // Bitwise, like the file: fps is stored, not computed.
  if (std::memcmp(&a.fps, &b.fps, sizeof a.fps) != 0)
    return "fps " + number_text(a.fps) + " vs " + number_text(b.fps);
  if (a.num_lr_nodes != b.num_lr_nodes)
    return "LR node count " + std::to_string(a.num_lr_nodes) + " vs " + std::to_string(b.num_lr_nodes);
  if (a.num_surface != b.num_surface)
    return "surface vertex count " + std::to_string(a.num_surface) + " vs " + std::to_string(b.num_surface);
  if (a.weight_names.size() != b.weight_names.size())
    return "weight count " + std::to_string(a.weight_names.size()) + " vs " + std::to_string(b.weight_names.size());
  for (size_t i = 0; i < a.weight_names.size(); ++i)
    if (a.weight_names[i] != b.weight_names[i])
      return "weight " + std::to_string(i) + " '" + a.weight_names[i] + "' vs '" + b.weight_names[i] + "'";
  return "";
}

std::vector<uint8_t> encode_header(const DatasetHeader& h, const std::array<char, 8>& magic, bool with_frame_count,
                                   uint64_t* frame_count_offset) {
  ByteWriter w;
  w.put(magic);
  w.put<uint32_t>(kVersion);
  w.put_string(h.units);
  w.put_string(h.name);
  w.put<uint64_t>(h.rig_checksum);
  w.put<double>(h.fps);
  w.put<uint64_t>(h.num_lr_nodes);
  w.put<uint64_t>(h.num_surface);
  w.put<uint64_t>(h.weight_names.size());
  for (const std::string& s : h.weight_names) w.put_string(s);
  if (with_frame_count) {
    if (frame_count_offset) *frame_count_offset = w.bytes().size();
    w.put<uint64_t>(h.num_frames);
  }
  return std::move(w.bytes());
}

void validate_frame(const DatasetHeader& h, const DatasetFrame& f, const std::string& where,
                    const double* previous_time) {
  auto size_ok = [&](const std::vector<float>& v, uint64_t expected, const char* what) {
    require(v.size() == expected, where + ": " + what + " has " + std::to_string(v.size()) + " floats, expected " +
                                      std::to_string(expected));
  };
  size_ok(f.weights, h.weight_names.size(), "weights");
  size_ok(f.lr_disp, 3 * h.num_lr_nodes, "lr_disp");
  size_ok(f.hr_disp, 3 * h.num_surface, "hr_disp");
  size_ok(f.embedded_disp, 3 * h.num_surface, "embedded_disp");

  require(std::isfinite(f.time), where + ": time is " + number_text(f.time) + " (must be finite)");
  if (previous_time)
    require(f.time > *previous_time, where + ": time " + number_text(f.time) + " s is not after the previous frame's " +
                                         number_text(*previous_time) + " s (times must be strictly increasing)");
  if (const long i = first_non_finite(f.weights); i >= 0)
    throw Error(where + ": weight " + std::to_string(i) + " ('" + h.weight_names[size_t(i)] + "') is " +
                number_text(f.weights[size_t(i)]));
  for (size_t i = 0; i < f.jaw.size(); ++i)
    require(std::isfinite(f.jaw[i]), where + ": jaw transform entry " + std::to_string(i) + " is " +
                                         number_text(f.jaw[i]));
  auto coords_ok = [&](const std::vector<float>& v, const char* what, const char* item) {
    if (const long i = first_non_finite(v); i >= 0)
      throw Error(where + ": " + what + " " + item + " " + std::to_string(i / 3) + " has a non-finite coordinate (" +
                  number_text(v[size_t(i)]) + ")");
  };
  coords_ok(f.lr_disp, "lr_disp", "node");
  coords_ok(f.hr_disp, "hr_disp", "vertex");
  coords_ok(f.embedded_disp, "embedded_disp", "vertex");

  const DatasetFrameStats& s = f.stats;
  auto stat_ok = [&](double v, const char* what) {
    require(std::isfinite(v) && (v >= 0 || v == -1),
            where + ": stat " + what + " is " + number_text(v) + " (must be >= 0, or -1 for not measured)");
  };
  stat_ok(s.hr_step_s, "hr_step_s");
  stat_ok(s.lr_step_ms, "lr_step_ms");
  stat_ok(s.max_penetration_cm, "max_penetration_cm");
  stat_ok(s.max_penetration_free_cm, "max_penetration_free_cm");
  stat_ok(s.contacts, "contacts");
  stat_ok(s.hr_newton_iters, "hr_newton_iters");
  stat_ok(s.hr_cg_iters, "hr_cg_iters");
  stat_ok(s.lr_newton_iters, "lr_newton_iters");
  stat_ok(s.lr_cg_iters, "lr_cg_iters");
  stat_ok(s.hr_rel_residual, "hr_rel_residual");
  stat_ok(s.lr_rel_residual, "lr_rel_residual");
}

void encode_frame(const DatasetHeader& h, const DatasetFrame& f, uint8_t* p) {
  put(p, f.time);
  put_floats(p, f.weights.data(), f.weights.size());
  put_floats(p, f.jaw.data(), f.jaw.size());
  put_floats(p, f.lr_disp.data(), f.lr_disp.size());
  put_floats(p, f.hr_disp.data(), f.hr_disp.size());
  put_floats(p, f.embedded_disp.data(), f.embedded_disp.size());
  // Field by field: the struct has padding, and the file must not depend on it.
  const DatasetFrameStats& s = f.stats;
  put(p, s.hr_step_s);
  put(p, s.lr_step_ms);
  put(p, s.max_penetration_cm);
  put(p, s.max_penetration_free_cm);
  put(p, s.contacts);
  put(p, s.hr_newton_iters);
  put(p, s.hr_cg_iters);
  put(p, s.lr_newton_iters);
  put(p, s.lr_cg_iters);
  put(p, s.hr_rel_residual);
  put(p, s.lr_rel_residual);
}

void decode_frame(const DatasetHeader& h, const uint8_t* p, DatasetFrame& f) {
  take(p, f.time);
  f.weights.resize(h.weight_names.size());
  f.lr_disp.resize(3 * h.num_lr_nodes);
  f.hr_disp.resize(3 * h.num_surface);
  f.embedded_disp.resize(3 * h.num_surface);
  take_floats(p, f.weights.data(), f.weights.size());
  take_floats(p, f.jaw.data(), f.jaw.size());
  take_floats(p, f.lr_disp.data(), f.lr_disp.size());
  take_floats(p, f.hr_disp.data(), f.hr_disp.size());
  take_floats(p, f.embedded_disp.data(), f.embedded_disp.size());
  DatasetFrameStats& s = f.stats;
  take(p, s.hr_step_s);
  take(p, s.lr_step_ms);
  take(p, s.max_penetration_cm);
  take(p, s.max_penetration_free_cm);
  take(p, s.contacts);
  take(p, s.hr_newton_iters);
  take(p, s.hr_cg_iters);
  take(p, s.lr_newton_iters);
  take(p, s.lr_cg_iters);
  take(p, s.hr_rel_residual);
  take(p, s.lr_rel_residual);
}

FileReader::FileReader(const std::string& path) : path_(path), in_(path, std::ios::binary), hash_(fnv1a64(nullptr, 0)) {
  require(in_.good(), "cannot open '" + path + "': no such file or not readable");
  in_.seekg(0, std::ios::end);
  const auto size = in_.tellg();
  require(size >= 0, "cannot read '" + path + "'");
  size_ = uint64_t(size);
  in_.seekg(0);
}

void FileReader::read(void* out, uint64_t n, const char* what) {
  if (n > remaining()) {
    truncated_ = true;
    throw Error(path_ + ": truncated while reading " + what);
  }
  in_.read(static_cast<char*>(out), std::streamsize(n));
  require(uint64_t(in_.gcount()) == n, path_ + ": read failed while reading " + what);
  hash_ = fnv1a64(out, n, hash_);
  pos_ += n;
}

std::string FileReader::get_string(const char* what) {
  const auto n = get<uint64_t>(what);
  require(n <= (1u << 20), path_ + ": " + what + " has an implausible length " + std::to_string(n));
  std::string s(n, '\0');
  read(s.data(), n, what);
  return s;
}

}  // namespace facesr::fsd
