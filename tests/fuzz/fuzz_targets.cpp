#include "fuzz_targets.h"

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/checksum.h"
#include "core/error.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "mesh/obj_io.h"
#include "perf/livelink_csv.h"
#include "perf/performance.h"
#include "perf/sequence_io.h"
#include "rig/rig_io.h"
#include "sr/sr_model.h"
#include "tiny_files.h"

namespace fs = std::filesystem;

namespace facesr::fuzz {

namespace {

// The loaders read paths, as every caller uses them, so the input goes
// through a file: one per process (libFuzzer's -fork/-jobs workers run side
// by side), in memory where /dev/shm exists.
std::string scratch_path(const char* extension) {
  static const std::string dir = [] {
    const char* env = std::getenv("FACESR_FUZZ_TMP");
    std::string d = env ? env : (fs::is_directory("/dev/shm") ? "/dev/shm" : fs::temp_directory_path().string());
    d += "/facesr-fuzz-" + std::to_string(::getpid());
    fs::create_directories(d);
    return d;
  }();
  return dir + "/input" + extension;
}

std::string put(const uint8_t* data, size_t size, const char* extension) {
  const std::string p = scratch_path(extension);
  std::FILE* f = std::fopen(p.c_str(), "wb");
  if (!f) throw std::runtime_error("fuzz harness: cannot write " + p);
  if (size > 0 && std::fwrite(data, 1, size, f) != size) throw std::runtime_error("fuzz harness: short write");
  std::fclose(f);
  return p;
}

// Runs the loader; a facesr::Error is a rejection, anything else escapes.
template <class F>
Outcome attempt(F&& load) {
  try {
    load();
    return Outcome::Accepted;
  } catch (const Error&) {
    return Outcome::Rejected;
  }
}

template <class Load>
Outcome binary(const uint8_t* data, size_t size, const char* ext,
               std::vector<uint8_t> (*reseal)(const uint8_t*, size_t), Load&& load) {
  const Outcome raw = attempt([&] { load(put(data, size, ext)); });
  const auto sealed = reseal(data, size);
  const Outcome fixed = attempt([&] { load(put(sealed.data(), sealed.size(), ext)); });
  return raw == Outcome::Accepted || fixed == Outcome::Accepted ? Outcome::Accepted : Outcome::Rejected;
}

Outcome rig(const uint8_t* d, size_t n) {
  return binary(d, n, ".rig", reseal_rig, [](const std::string& p) { (void)load_rig(p); });
}

Outcome model(const uint8_t* d, size_t n) {
  return binary(d, n, ".fsm", reseal_trailing_checksum, [](const std::string& p) { (void)load_sr_model(p); });
}

Outcome sequence(const uint8_t* d, size_t n) {
  return binary(d, n, ".fsq", reseal_trailing_checksum, [](const std::string& p) { (void)read_sequence(p); });
}

Outcome dataset(const uint8_t* d, size_t n) {
  return binary(d, n, ".fsd", reseal_trailing_checksum, [](const std::string& p) {
    (void)read_dataset_header(p);
    (void)read_dataset_sequence(p);
  });
}

// A killed `facesr dataset` run leaves "<name>.fsd.partial"; the next run
// resumes from whatever it holds.
Outcome dataset_partial(const uint8_t* d, size_t n) {
  const std::string target = scratch_path(".fsd");
  const std::string partial = DatasetWriter::partial_path_for(target);
  put(d, n, ".fsd.partial");  // scratch_path(".fsd.partial") == partial
  const Outcome o = attempt([&] {
    DatasetWriter w(target, tiny::dataset_header());
    (void)w.frames();
  });
  std::error_code ec;
  fs::remove(partial, ec);
  return o;
}

Outcome performance(const uint8_t* d, size_t n) {
  const std::string p = put(d, n, ".json");
  return attempt([&] { (void)load_performance(p, rig_names()); });
}

Outcome livelink(const uint8_t* d, size_t n) {
  const std::string p = put(d, n, ".csv");
  const Outcome lenient = attempt([&] {
    LiveLinkReport report;
    (void)load_livelink_csv(p, rig_names(), LiveLinkOptions(), &report);
    (void)livelink_report_json(report);
    (void)livelink_report_summary(report);
  });
  LiveLinkOptions strict;
  strict.strict = true;
  const Outcome s = attempt([&] { (void)load_livelink_csv(p, rig_names(), strict); });
  return lenient == Outcome::Accepted || s == Outcome::Accepted ? Outcome::Accepted : Outcome::Rejected;
}

Outcome obj(const uint8_t* d, size_t n) {
  const std::string p = put(d, n, ".obj");
  const Outcome mesh = attempt([&] { (void)read_obj(p); });
  const Outcome verts = attempt([&] { (void)read_obj_vertices(p); });
  return mesh == Outcome::Accepted || verts == Outcome::Accepted ? Outcome::Accepted : Outcome::Rejected;
}

Outcome manifest(const uint8_t* d, size_t n) {
  const std::string p = put(d, n, ".json");
  return attempt([&] { (void)load_manifest(p); });
}

}  // namespace

std::vector<uint8_t> reseal_trailing_checksum(const uint8_t* data, size_t size) {
  std::vector<uint8_t> b(data, data + size);
  if (b.size() < 8) return b;
  const uint64_t c = fnv1a64(b.data(), b.size() - 8);
  std::memcpy(b.data() + b.size() - 8, &c, 8);
  return b;
}

std::vector<uint8_t> reseal_rig(const uint8_t* data, size_t size) {
  constexpr size_t header = 24, checksum = 8;
  std::vector<uint8_t> b(data, data + size);
  if (b.size() < header + checksum) return b;
  const uint64_t payload = b.size() - header - checksum;
  std::memcpy(b.data() + 16, &payload, 8);
  const uint64_t c = fnv1a64(b.data() + header, payload);
  std::memcpy(b.data() + header + payload, &c, 8);
  return b;
}

const std::vector<std::string>& rig_names() {
  static const std::vector<std::string> names = {
      "browDown_L",       "browDown_R",       "browInnerUp_L",   "browInnerUp_R",   "browOuterUp_L",
      "browOuterUp_R",    "cheekPuff_L",      "cheekPuff_R",     "cheekSquint_L",   "cheekSquint_R",
      "eyeBlink_L",       "eyeBlink_R",       "eyeLookDown_L",   "eyeLookDown_R",   "eyeLookIn_L",
      "eyeLookIn_R",      "eyeLookOut_L",     "eyeLookOut_R",    "eyeLookUp_L",     "eyeLookUp_R",
      "eyeSquint_L",      "eyeSquint_R",      "eyeWide_L",       "eyeWide_R",       "jawForward",
      "jawLeft",          "jawOpen",          "jawRight",        "mouthClose",      "mouthDimple_L",
      "mouthDimple_R",    "mouthFrown_L",     "mouthFrown_R",    "mouthFunnel",     "mouthLeft",
      "mouthLowerDown_L", "mouthLowerDown_R", "mouthPress_L",    "mouthPress_R",    "mouthPucker",
      "mouthRight",       "mouthRollLower",   "mouthRollUpper",  "mouthShrugLower", "mouthShrugUpper",
      "mouthSmile_L",     "mouthSmile_R",     "mouthStretch_L",  "mouthStretch_R",  "mouthUpperUp_L",
      "mouthUpperUp_R",   "noseSneer_L",      "noseSneer_R"};
  return names;
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"rig", ".rig", rig},
      {"model", ".fsm", model},
      {"sequence", ".fsq", sequence},
      {"dataset", ".fsd", dataset},
      {"dataset_partial", ".partial", dataset_partial},
      {"performance", ".json", performance},
      {"livelink", ".csv", livelink},
      {"obj", ".obj", obj},
      {"manifest", ".json", manifest},
  };
  return all;
}

const Target* find_target(const std::string& name) {
  for (const auto& t : targets())
    if (name == t.name) return &t;
  return nullptr;
}

}  // namespace facesr::fuzz
