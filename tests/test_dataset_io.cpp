// Paired LR/HR dataset sequences (.fsd): bit-exact round trip, rejection of
// damaged files, the resumable writer (recovering complete frames after a
// kill, refusing another header), the manifest, the embedded-error metric and
// the error heat-map picture.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "dataset/dataset_metrics.h"
#include "render/error_render.h"
#include "render/sequence_render.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;

namespace {

using fixtures::error_of;

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

constexpr int kN = 7, kS = 5, kB = 3;

DatasetHeader make_header() {
  DatasetHeader h;
  h.name = "talk";
  h.rig_checksum = 0xfedcba9876543210ull;
  h.fps = 24;
  h.num_lr_nodes = kN;
  h.num_surface = kS;
  h.weight_names = {"jawOpen", "mouthSmile_L", "browInnerUp"};
  return h;
}

// Frame f with values of every bit-pattern class: negatives, tiny, large, -0,
// and stats with "not measured" (-1) next to measured ones.
DatasetFrame make_frame(int f) {
  DatasetFrame fr;
  fr.time = 0.05 + f / 24.0;
  for (int i = 0; i < kB; ++i) fr.weights.push_back(float(0.1 * i + 0.2 * f));
  for (int i = 0; i < 12; ++i) fr.jaw[i] = float(std::sin(0.3 * i + f));
  for (int i = 0; i < kN * 3; ++i) fr.lr_disp.push_back(float(std::sin(0.37 * i + f)) * 0.5f + 1e-7f * i);
  for (int i = 0; i < kS * 3; ++i) {
    fr.hr_disp.push_back(i == 0 ? -0.0f : float(std::cos(0.11 * i - f)) * 3e3f);
    fr.embedded_disp.push_back(float(std::cos(0.11 * i - f)) * 3e3f + 1e-3f * i);
  }
  DatasetFrameStats& s = fr.stats;
  s.hr_step_s = 12.5 + f;
  s.lr_step_ms = 3.25;
  s.max_penetration_cm = 0.01f * f;
  s.max_penetration_free_cm = f % 2 ? 0.3f : -1.0f;
  s.contacts = 10 * f;
  s.hr_newton_iters = 4;
  s.hr_cg_iters = 300 + f;
  s.lr_newton_iters = 3;
  s.lr_cg_iters = 60;
  s.hr_rel_residual = 1e-4f;
  s.lr_rel_residual = -1;
  return fr;
}

DatasetSequence make_sequence(int frames) {
  DatasetSequence s;
  s.header = make_header();
  for (int f = 0; f < frames; ++f) s.frames.push_back(make_frame(f));
  return s;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every field, bit for bit (so -0 and the exact float values survive).
void expect_same_frame(const DatasetFrame& a, const DatasetFrame& b, int f) {
  SCOPED_TRACE("frame " + std::to_string(f));
  EXPECT_TRUE(same_bits(a.time, b.time));
  EXPECT_TRUE(same_bits(a.weights, b.weights));
  EXPECT_TRUE(same_bits(a.jaw, b.jaw));
  EXPECT_TRUE(same_bits(a.lr_disp, b.lr_disp));
  EXPECT_TRUE(same_bits(a.hr_disp, b.hr_disp));
  EXPECT_TRUE(same_bits(a.embedded_disp, b.embedded_disp));
  const DatasetFrameStats &s = a.stats, &t = b.stats;
  EXPECT_TRUE(same_bits(s.hr_step_s, t.hr_step_s));
  EXPECT_TRUE(same_bits(s.lr_step_ms, t.lr_step_ms));
  EXPECT_TRUE(same_bits(s.max_penetration_cm, t.max_penetration_cm));
  EXPECT_TRUE(same_bits(s.max_penetration_free_cm, t.max_penetration_free_cm));
  EXPECT_EQ(s.contacts, t.contacts);
  EXPECT_EQ(s.hr_newton_iters, t.hr_newton_iters);
  EXPECT_EQ(s.hr_cg_iters, t.hr_cg_iters);
  EXPECT_EQ(s.lr_newton_iters, t.lr_newton_iters);
  EXPECT_EQ(s.lr_cg_iters, t.lr_cg_iters);
  EXPECT_TRUE(same_bits(s.hr_rel_residual, t.hr_rel_residual));
  EXPECT_TRUE(same_bits(s.lr_rel_residual, t.lr_rel_residual));
}

std::vector<char> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(b.data(), std::streamsize(b.size()));
}

void append_bytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::app);
  out.write(b.data(), std::streamsize(b.size()));
}

// Documented layout sizes (dataset_io.h).
size_t header_bytes(const DatasetHeader& h) {
  size_t n = 8 + 4 + (8 + h.units.size()) + (8 + h.name.size()) + 8 + 8 + 8 + 8 + 8 + 8;
  for (const auto& w : h.weight_names) n += 8 + w.size();
  return n;
}
constexpr size_t kFrameBytes = 8 + 4 * kB + 48 + 12 * kN + 24 * kS + 52;

class TempDir : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("facesr_ds_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  void TearDown() override {
    for (const auto& e : fs::directory_iterator(dir_)) fs::remove_all(e.path());
  }
  static std::vector<std::string> files() {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  static fs::path dir_;
};
fs::path TempDir::dir_;

class DatasetIO : public TempDir {};
class DatasetManifestIO : public TempDir {};
class ErrorRender : public TempDir {};

}  // namespace

TEST_F(DatasetIO, RoundTripIsBitExact) {
  const DatasetSequence s = make_sequence(4);
  const fs::path p = dir_ / "talk.fsd";
  write_dataset_sequence(p.string(), s);
  EXPECT_EQ(files(), std::vector<std::string>{"talk.fsd"}) << "no partial or temporary file remains";

  const DatasetSequence r = read_dataset_sequence(p.string());
  const DatasetHeader& h = r.header;
  EXPECT_EQ(h.units, "cm");
  EXPECT_EQ(h.name, "talk");
  EXPECT_EQ(h.rig_checksum, s.header.rig_checksum);
  EXPECT_EQ(h.fps, 24);
  EXPECT_EQ(h.num_lr_nodes, uint64_t(kN));
  EXPECT_EQ(h.num_surface, uint64_t(kS));
  EXPECT_EQ(h.weight_names, s.header.weight_names);
  EXPECT_EQ(h.num_frames, 4u);
  ASSERT_EQ(r.num_frames(), 4);
  for (int f = 0; f < 4; ++f) expect_same_frame(r.frame(f), s.frames[f], f);
  EXPECT_TRUE(std::signbit(r.frame(0).hr_disp[0]));  // -0 survives
  EXPECT_EQ(r.weight_index("browInnerUp"), 2);
  EXPECT_EQ(r.weight_index("nope"), -1);

  EXPECT_EQ(fs::file_size(p), header_bytes(s.header) + 4 * kFrameBytes + 8);

  const DatasetHeader only = read_dataset_header(p.string());
  EXPECT_EQ(only.name, "talk");
  EXPECT_EQ(only.num_frames, 4u);
  EXPECT_EQ(only.weight_names, s.header.weight_names);
}

TEST_F(DatasetIO, TruncatedFileIsRejected) {
  const fs::path p = dir_ / "t.fsd";
  write_dataset_sequence(p.string(), make_sequence(4));
  const std::vector<char> full = read_bytes(p);
  const size_t header = header_bytes(make_header());
  for (size_t cut : {size_t(3), size_t(10), size_t(40), header - 5, header + kFrameBytes / 2,
                     header + 2 * kFrameBytes + 17, full.size() - 8, full.size() - 1}) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    write_bytes(p, std::vector<char>(full.begin(), full.begin() + long(cut)));
    const std::string msg = error_of([&] { read_dataset_sequence(p.string()); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, "truncated");
    if (cut < header) EXPECT_HAS(error_of([&] { read_dataset_header(p.string()); }), "truncated");
  }
}

TEST_F(DatasetIO, FlippedByteAndTrailingBytesAreRejected) {
  const fs::path p = dir_ / "c.fsd";
  write_dataset_sequence(p.string(), make_sequence(4));
  const std::vector<char> b = read_bytes(p);
  const size_t header = header_bytes(make_header());
  for (size_t at : {header + 3, header + kFrameBytes + kFrameBytes / 2, b.size() - 20, b.size() - 1}) {
    std::vector<char> bad = b;
    bad[at] ^= 0x10;
    write_bytes(p, bad);
    const std::string msg = error_of([&] { read_dataset_sequence(p.string()); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, "checksum mismatch");
  }
  for (size_t extra : {size_t(1), kFrameBytes + 8}) {
    std::vector<char> longer = b;
    longer.resize(b.size() + extra, 0);
    write_bytes(p, longer);
    const std::string msg = error_of([&] { read_dataset_sequence(p.string()); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, "trailing");
  }
}

TEST_F(DatasetIO, WrongMagicVersionPartialAndMissingFile) {
  const fs::path p = dir_ / "m.fsd";
  write_dataset_sequence(p.string(), make_sequence(1));
  const std::vector<char> b = read_bytes(p);
  std::vector<char> bad = b;
  std::memcpy(bad.data(), "FACESRSQ", 8);  // a sequence file is not a dataset
  write_bytes(p, bad);
  EXPECT_HAS(error_of([&] { read_dataset_sequence(p.string()); }), "not a facesr dataset file");
  EXPECT_HAS(error_of([&] { read_dataset_header(p.string()); }), "FACESRSQ");
  bad = b;
  bad[8] = 2;
  write_bytes(p, bad);
  EXPECT_HAS(error_of([&] { read_dataset_sequence(p.string()); }), "unsupported dataset format version 2");

  const fs::path q = dir_ / "open.fsd";
  {
    DatasetWriter w(q.string(), make_header());
    w.add_frame(make_frame(0));
  }
  const std::string partial = DatasetWriter::partial_path_for(q.string());
  EXPECT_HAS(error_of([&] { read_dataset_sequence(partial); }), "unfinished partial dataset file");

  const std::string missing = (dir_ / "missing.fsd").string();
  EXPECT_HAS(error_of([&] { read_dataset_sequence(missing); }), missing);
}

TEST_F(DatasetIO, WriterKeepsThePartialFileUntilCommit) {
  const fs::path p = dir_ / "w.fsd";
  const DatasetSequence s = make_sequence(2);
  DatasetWriter w(p.string(), s.header);
  EXPECT_EQ(w.frames(), 0u);
  EXPECT_EQ(w.recovered_frames(), 0u);
  for (const DatasetFrame& f : s.frames) w.add_frame(f);
  EXPECT_FALSE(fs::exists(p)) << "nothing at the final path before commit()";
  EXPECT_EQ(files(), std::vector<std::string>{"w.fsd.partial"});
  // Flushed per frame: the partial file already holds both frames and their checksums.
  const size_t partial_header = header_bytes(s.header) - 8 + 8;  // no frame count, plus header checksum
  EXPECT_EQ(fs::file_size(w.partial_path()), partial_header + 2 * (kFrameBytes + 8));
  w.commit();
  EXPECT_EQ(files(), std::vector<std::string>{"w.fsd"});
  EXPECT_HAS(error_of([&] { w.add_frame(make_frame(5)); }), "closed");

  DatasetWriter empty((dir_ / "e.fsd").string(), s.header);
  EXPECT_HAS(error_of([&] { empty.commit(); }), "no frames");
}

TEST_F(DatasetIO, ResumeKeepsCompleteFramesAndCutsAHalfWrittenOne) {
  const DatasetSequence s = make_sequence(5);
  const size_t record = kFrameBytes + 8;
  // A kill in the middle of a frame, and a whole frame's worth of garbage.
  for (size_t garbage : {record / 2, record, record + 5}) {
    SCOPED_TRACE("garbage bytes " + std::to_string(garbage));
    const fs::path p = dir_ / "r.fsd";
    const std::string partial = DatasetWriter::partial_path_for(p.string());
    {
      DatasetWriter w(p.string(), s.header);
      for (int f = 0; f < 3; ++f) w.add_frame(s.frames[f]);
    }  // destroyed without commit: the partial file is the resume point
    ASSERT_TRUE(fs::exists(partial));
    EXPECT_FALSE(fs::exists(p));
    const auto good_size = fs::file_size(partial);
    std::vector<char> junk(garbage);
    for (size_t i = 0; i < garbage; ++i) junk[i] = char(i * 37 + 11);
    append_bytes(partial, junk);

    {
      DatasetWriter w(p.string(), s.header);
      EXPECT_EQ(w.frames(), 3u);
      EXPECT_EQ(w.recovered_frames(), 3u);
      EXPECT_EQ(w.discarded_bytes(), garbage);
      EXPECT_EQ(w.last_time(), s.frames[2].time);
      EXPECT_EQ(fs::file_size(partial), good_size) << "the half frame is cut off";
      // Times continue from the recovered frames.
      EXPECT_HAS(error_of([&] { w.add_frame(s.frames[1]); }), "strictly increasing");
      w.add_frame(s.frames[3]);
      w.add_frame(s.frames[4]);
      w.commit();
    }
    EXPECT_FALSE(fs::exists(partial));
    const DatasetSequence r = read_dataset_sequence(p.string());
    ASSERT_EQ(r.num_frames(), 5);
    for (int f = 0; f < 5; ++f) expect_same_frame(r.frame(f), s.frames[f], f);
    fs::remove(p);
  }
}

TEST_F(DatasetIO, ResumeWithAnotherHeaderIsAnError) {
  const fs::path p = dir_ / "h.fsd";
  const std::string partial = DatasetWriter::partial_path_for(p.string());
  {
    DatasetWriter w(p.string(), make_header());
    w.add_frame(make_frame(0));
    w.add_frame(make_frame(1));
  }
  const auto before = read_bytes(partial);
  DatasetHeader other = make_header();
  other.rig_checksum = 1;
  std::string msg = error_of([&] { DatasetWriter w(p.string(), other); });
  EXPECT_HAS(msg, partial);
  EXPECT_HAS(msg, "different header");
  EXPECT_HAS(msg, "rig checksum");
  other = make_header();
  other.weight_names[1] = "mouthSmile_R";
  EXPECT_HAS(error_of([&] { DatasetWriter w(p.string(), other); }), "mouthSmile_R");
  EXPECT_TRUE(read_bytes(partial) == before) << "a refused resume leaves the partial file alone";

  // The frame count is not part of the comparison.
  DatasetHeader counted = make_header();
  counted.num_frames = 99;
  EXPECT_EQ(DatasetWriter(p.string(), counted).frames(), 2u);

  // restart discards the old partial file.
  other.rig_checksum = 1;
  {
    DatasetWriter w(p.string(), other, /*restart=*/true);
    EXPECT_EQ(w.frames(), 0u);
    w.add_frame(make_frame(3));
    w.commit();
  }
  const DatasetSequence r = read_dataset_sequence(p.string());
  EXPECT_EQ(r.header.rig_checksum, 1u);
  ASSERT_EQ(r.num_frames(), 1);
  expect_same_frame(r.frame(0), make_frame(3), 0);

  // A file at the partial path that is not a partial dataset file.
  write_bytes(partial, std::vector<char>(100, 'x'));
  EXPECT_HAS(error_of([&] { DatasetWriter w(p.string(), make_header()); }), "not a facesr dataset partial file");
  // A partial file cut inside its header holds nothing, so it is started over.
  write_bytes(partial, std::vector<char>(before.begin(), before.begin() + 30));
  EXPECT_EQ(DatasetWriter(p.string(), make_header()).frames(), 0u);
}

TEST_F(DatasetIO, WriterRejectsBadFramesWithoutCorruptingTheFile) {
  const fs::path p = dir_ / "bad.fsd";
  const DatasetSequence s = make_sequence(3);
  DatasetWriter w(p.string(), s.header);
  w.add_frame(s.frames[0]);
  w.add_frame(s.frames[1]);
  const auto before = read_bytes(w.partial_path());

  struct Case {
    DatasetFrame frame;
    const char* problem;
  };
  std::vector<Case> cases;
  DatasetFrame f = s.frames[2];
  f.hr_disp[7] = std::nanf("");
  cases.push_back({f, "frame 2: hr_disp vertex 2 has a non-finite coordinate"});
  f = s.frames[2];
  f.lr_disp.pop_back();
  cases.push_back({f, "lr_disp has 20 floats, expected 21"});
  f = s.frames[2];
  f.weights.push_back(0);
  cases.push_back({f, "weights has 4 floats, expected 3"});
  f = s.frames[2];
  f.jaw[4] = std::numeric_limits<float>::infinity();
  cases.push_back({f, "jaw transform entry 4"});
  f = s.frames[2];
  f.stats.hr_step_s = std::nan("");
  cases.push_back({f, "hr_step_s"});
  f = s.frames[2];
  f.stats.contacts = -5;
  cases.push_back({f, "contacts is -5"});
  f = s.frames[2];
  f.time = s.frames[1].time;
  cases.push_back({f, "strictly increasing"});
  for (const Case& c : cases) {
    const std::string msg = error_of([&] { w.add_frame(c.frame); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, c.problem);
    EXPECT_TRUE(read_bytes(w.partial_path()) == before) << c.problem;
    EXPECT_EQ(w.frames(), 2u);
  }
  w.add_frame(s.frames[2]);  // still usable
  w.commit();
  const DatasetSequence r = read_dataset_sequence(p.string());
  ASSERT_EQ(r.num_frames(), 3);
  for (int i = 0; i < 3; ++i) expect_same_frame(r.frame(i), s.frames[i], i);
}

TEST_F(DatasetIO, BadHeadersAreRejectedByTheWriter) {
  const fs::path p = dir_ / "h.fsd";
  auto msg_for = [&](const DatasetHeader& h) { return error_of([&] { DatasetWriter w(p.string(), h); }); };
  DatasetHeader h = make_header();
  h.units = "mm";
  EXPECT_HAS(msg_for(h), "units are 'mm', expected 'cm'");
  h = make_header();
  h.name = "";
  EXPECT_HAS(msg_for(h), "performance name is empty");
  h = make_header();
  h.fps = 0;
  EXPECT_HAS(msg_for(h), "not in (0, 1000]");
  h = make_header();
  h.num_surface = 0;
  EXPECT_HAS(msg_for(h), "surface vertex count 0");
  h = make_header();
  h.weight_names[2] = "jawOpen";
  EXPECT_HAS(msg_for(h), "'jawOpen' appears twice");
  EXPECT_TRUE(files().empty());
  const std::string missing = (dir_ / "no_dir" / "x.fsd").string();
  EXPECT_HAS(error_of([&] { DatasetWriter w(missing, make_header()); }), missing);
}

TEST_F(DatasetManifestIO, RoundTrip) {
  DatasetManifest m;
  m.rig_name = "ict";
  m.rig_checksum = 0xfedcba9876543210ull;  // above 2^63: must survive JSON
  m.rig_path = "out/ict.rig";
  m.fps = 30;
  m.num_lr_nodes = 1234;
  m.num_surface = 5678;
  m.weight_names = {"jawOpen", "mouthSmile_L"};
  DatasetManifest::Entry e;
  e.name = "talk";
  e.file = "talk.fsd";
  e.frames = 90;
  e.split = "test";
  e.hr_mean_step_s = 14.5;
  e.lr_mean_step_ms = 3.2;
  e.embedded_error_mean_cm = 0.031;
  e.embedded_error_max_cm = 0.27;
  e.max_penetration_cm = 0.002;
  e.complete = true;
  m.sequences.push_back(e);
  e.name = "smile";
  e.file = "smile.fsd";
  e.split = "train";
  e.complete = false;
  m.sequences.push_back(e);
  m.extra = {{"solver", "accurate"}, {"collisions", true}};

  const std::string p = (dir_ / "manifest.json").string();
  save_manifest(p, m);
  EXPECT_EQ(files(), std::vector<std::string>{"manifest.json"});
  const DatasetManifest r = load_manifest(p);
  EXPECT_EQ(manifest_to_json(r), manifest_to_json(m));
  EXPECT_EQ(r.rig_checksum, m.rig_checksum);
  ASSERT_EQ(r.sequences.size(), 2u);
  EXPECT_EQ(r.sequences[0].split, "test");
  EXPECT_EQ(r.sequences[1].complete, false);
  EXPECT_EQ(r.extra["solver"], "accurate");
  ASSERT_NE(r.find("smile"), nullptr);
  EXPECT_EQ(r.find("smile")->file, "smile.fsd");
  EXPECT_EQ(r.find("nope"), nullptr);

  // Keys are the field names.
  std::ifstream in(p);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["format"], "facesr-dataset");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["units"], "cm");
  EXPECT_EQ(j["sequences"][0]["embedded_error_max_cm"], 0.27);
}

TEST_F(DatasetManifestIO, MalformedManifestsAreRejected) {
  DatasetManifest m;
  m.rig_name = "procedural";
  m.num_lr_nodes = 10;
  m.num_surface = 20;
  DatasetManifest::Entry e;
  e.name = "talk";
  e.file = "talk.fsd";
  m.sequences.push_back(e);
  const nlohmann::json good = manifest_to_json(m);
  const std::string p = (dir_ / "m.json").string();
  auto msg_for = [&](const nlohmann::json& j) {
    std::ofstream(p) << j.dump();
    return error_of([&] { load_manifest(p); });
  };

  std::ofstream(p) << "{ \"format\": ";
  std::string msg = error_of([&] { load_manifest(p); });
  EXPECT_HAS(msg, p);
  EXPECT_HAS(msg, "not valid JSON");

  nlohmann::json j = good;
  j["format"] = "facesr-rig";
  EXPECT_HAS(msg_for(j), "format is 'facesr-rig'");
  j = good;
  j["version"] = 2;
  EXPECT_HAS(msg_for(j), "unsupported manifest version 2");
  j = good;
  j["units"] = "mm";
  EXPECT_HAS(msg_for(j), "units are 'mm'");
  j = good;
  j.erase("rig_checksum");
  EXPECT_HAS(msg_for(j), "rig_checksum is missing");
  j = good;
  j["rig_checksum"] = -3;
  EXPECT_HAS(msg_for(j), "rig_checksum is not an unsigned integer");
  j = good;
  j["num_surface"] = "20";
  EXPECT_HAS(msg_for(j), "num_surface is not an integer");
  j = good;
  j["sequences"][0].erase("split");
  msg = msg_for(j);
  EXPECT_HAS(msg, p);
  EXPECT_HAS(msg, "sequences[0].split is missing");
  j = good;
  j["sequences"][0]["split"] = "val";
  EXPECT_HAS(msg_for(j), "sequences[0].split is 'val', expected 'train' or 'test'");
  j = good;
  j["sequences"][0]["frames"] = -1;
  EXPECT_HAS(msg_for(j), "sequences[0].frames is -1");
  j = good;
  j["sequences"][0]["complete"] = 1;
  EXPECT_HAS(msg_for(j), "sequences[0].complete is not true or false");
  j = good;
  j["sequences"].push_back(good["sequences"][0]);
  EXPECT_HAS(msg_for(j), "sequences[1].name 'talk' appears twice");
  EXPECT_HAS(msg_for(nlohmann::json::array()), "must be a JSON object");
  EXPECT_HAS(error_of([&] { load_manifest((dir_ / "none.json").string()); }), "none.json");

  // save_manifest refuses what load_manifest would, and writes nothing.
  DatasetManifest bad = m;
  bad.sequences[0].split = "validation";
  const std::string q = (dir_ / "bad.json").string();
  EXPECT_HAS(error_of([&] { save_manifest(q, bad); }), "split is 'validation'");
  bad = m;
  bad.sequences[0].embedded_error_mean_cm = std::nan("");
  EXPECT_HAS(error_of([&] { save_manifest(q, bad); }), "embedded_error_mean_cm is not finite");
  EXPECT_FALSE(fs::exists(q));
}

TEST(DatasetMetrics, EmbeddedErrorOnAHandComputedCase) {
  DatasetFrame f;
  // Vertex 0 is off by (3, 4, 0) = 5 cm, vertex 1 by (-1, -2, 2) = 3 cm, vertex 2 exact.
  f.hr_disp = {3, 4, 0, 0, 0, 0, 1, 1, 1};
  f.embedded_disp = {0, 0, 0, 1, 2, -2, 1, 1, 1};
  double mean = -1, max = -1;
  embedded_error(f, mean, max);
  EXPECT_DOUBLE_EQ(mean, 8.0 / 3);
  EXPECT_DOUBLE_EQ(max, 5);
  const std::vector<float> d = embedded_error_per_vertex(f);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_FLOAT_EQ(d[0], 5);
  EXPECT_FLOAT_EQ(d[1], 3);
  EXPECT_FLOAT_EQ(d[2], 0);

  f.embedded_disp.pop_back();
  EXPECT_HAS(error_of([&] { embedded_error(f, mean, max); }), "embedded_disp");
}

namespace {

// Width and height from a PNG's IHDR chunk (big-endian, at bytes 16..23).
std::pair<int, int> png_size(const fs::path& p) {
  const std::vector<char> b = read_bytes(p);
  if (b.size() < 24 || std::memcmp(b.data() + 1, "PNG", 3) != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    return int((uint8_t(b[at]) << 24) | (uint8_t(b[at + 1]) << 16) | (uint8_t(b[at + 2]) << 8) | uint8_t(b[at + 3]));
  };
  return {be32(16), be32(20)};
}

// Pixels clearly red (the top of the heat scale, under any shading).
int red_pixels(const Image& img) {
  int n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const Rgb c = img.get(x, y);
      n += c.r > 2 * c.g && c.r > 2 * c.b;
    }
  return n;
}

}  // namespace

TEST_F(ErrorRender, WritesAHeatMapOfTheExpectedSize) {
  const Rig& rig = fixtures::procedural_rig();
  const int S = rig.num_surface_vertices();
  std::vector<float> rest(size_t(S) * 3);
  for (int v = 0; v < S; ++v)
    for (int k = 0; k < 3; ++k) rest[3 * v + k] = float(rig.surface(v, k));
  const double scale = 0.5;
  const std::vector<std::vector<float>> zero = {std::vector<float>(S, 0.0f)};
  const std::vector<std::vector<float>> high = {std::vector<float>(S, 0.7f)};  // saturates

  const fs::path p = dir_ / "err.png";
  render_error_png(rig, {rest, rest, rest}, {zero[0], high[0], zero[0]}, {"hr", "embedded", "t=0.50s"}, scale,
                   p.string(), 128);
  EXPECT_EQ(files(), std::vector<std::string>{"err.png"});
  const Image img = render_error_image(rig, {rest, rest, rest}, {zero[0], high[0], zero[0]},
                                       {"hr", "embedded", "t=0.50s"}, scale, 128);
  const auto [w, h] = png_size(p);
  EXPECT_EQ(w, img.width());
  EXPECT_EQ(h, img.height());
  EXPECT_EQ(w % 128, 0) << "whole tiles of the requested width";
  EXPECT_GE(w, 2 * 128) << "three panels are not stacked in one column";

  // Colour follows the error: a saturated panel is red where a zero one is blue.
  const int red_zero = red_pixels(render_error_image(rig, {rest}, zero, {"zero"}, scale, 128));
  const int red_high = red_pixels(render_error_image(rig, {rest}, high, {"high"}, scale, 128));
  EXPECT_GT(red_high, red_zero + 1000) << red_zero << " vs " << red_high;
}

TEST_F(ErrorRender, SizeMismatchIsAnErrorAndWritesNothing) {
  const Rig& rig = fixtures::procedural_rig();
  const int S = rig.num_surface_vertices();
  const std::vector<float> pos(size_t(S) * 3, 0.0f), err(S, 0.1f);
  const std::string p = (dir_ / "bad.png").string();
  std::string msg = error_of([&] { render_error_png(rig, {pos}, {std::vector<float>(S - 1, 0.1f)}, {"a"}, 1, p); });
  EXPECT_HAS(msg, "error values, expected " + std::to_string(S));
  msg = error_of([&] { render_error_png(rig, {std::vector<float>(3, 0.0f)}, {err}, {"a"}, 1, p); });
  EXPECT_HAS(msg, "surface vertices");
  EXPECT_HAS(error_of([&] { render_error_png(rig, {pos, pos}, {err}, {"a", "b"}, 1, p); }), "2 panels");
  EXPECT_HAS(error_of([&] { render_error_png(rig, {pos}, {err}, {"a"}, 0, p); }), "scale");
  EXPECT_HAS(error_of([&] { render_error_png(rig, {}, {}, {}, 1, p); }), "no panels");
  EXPECT_TRUE(files().empty());
}
