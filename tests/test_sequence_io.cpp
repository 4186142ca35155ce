// Sequence files (.fsq): bit-exact round trip, streaming writer guarantees
// (no partial or temporary file without commit) and rejection of damaged files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "core/error.h"
#include "perf/sequence_io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;

namespace {

using fixtures::error_of;

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

// Values that exercise every bit pattern class: negatives, tiny, large, -0.
Sequence make_sequence(int frames, int nodes, int surface) {
  Sequence s;
  s.header.resolution = "high";
  s.header.rig_checksum = 0x0123456789abcdefull;
  s.header.fps = 24;
  s.header.num_nodes = nodes;
  s.header.num_surface = surface;
  s.header.num_frames = frames;
  for (int f = 0; f < frames; ++f) {
    s.time.push_back(0.1 + f / 24.0);
    for (int i = 0; i < nodes * 3; ++i) s.nodes.push_back(float(std::sin(0.37 * i + f)) * 10.0f + 1e-7f * i);
    for (int i = 0; i < surface * 3; ++i) s.surface.push_back(i == 0 ? -0.0f : float(std::cos(0.11 * i - f)) * 3e3f);
  }
  return s;
}

std::vector<char> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& p, const std::vector<char>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(b.data(), std::streamsize(b.size()));
}

class SequenceIO : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("facesr_seq_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  // Any file in the folder other than `keep`: partial outputs or temporaries.
  static std::vector<std::string> leftovers(const std::string& keep = "") {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename() != keep) out.push_back(e.path().filename().string());
    return out;
  }
  void TearDown() override {
    for (const auto& e : fs::directory_iterator(dir_)) fs::remove_all(e.path());
  }
  static fs::path dir_;
};
fs::path SequenceIO::dir_;

}  // namespace

TEST_F(SequenceIO, RoundTripIsBitExact) {
  const Sequence s = make_sequence(5, 7, 11);
  const fs::path p = dir_ / "a.fsq";
  write_sequence(p.string(), s);
  EXPECT_TRUE(leftovers("a.fsq").empty());
  const Sequence r = read_sequence(p.string());
  EXPECT_EQ(r.header.units, "cm");
  EXPECT_EQ(r.header.resolution, "high");
  EXPECT_EQ(r.header.rig_checksum, s.header.rig_checksum);
  EXPECT_EQ(r.header.fps, 24);
  EXPECT_EQ(r.header.num_nodes, 7u);
  EXPECT_EQ(r.header.num_surface, 11u);
  EXPECT_EQ(r.header.num_frames, 5u);
  ASSERT_EQ(r.frames(), 5);
  EXPECT_EQ(std::memcmp(r.time.data(), s.time.data(), s.time.size() * sizeof(double)), 0);
  ASSERT_EQ(r.nodes.size(), s.nodes.size());
  ASSERT_EQ(r.surface.size(), s.surface.size());
  EXPECT_EQ(std::memcmp(r.nodes.data(), s.nodes.data(), s.nodes.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(r.surface.data(), s.surface.data(), s.surface.size() * sizeof(float)), 0);
  EXPECT_TRUE(std::signbit(r.surface[0]));  // -0 survives
  EXPECT_EQ(r.frame_surface(3)[2], s.surface[3 * 11 * 3 + 2]);

  // Documented layout: 8 magic + 4 version + strings + 6 × 8 header + frames + 8 checksum.
  const size_t header = 8 + 4 + (8 + 2) + (8 + 4) + 8 + 8 + 8 + 8 + 8;
  EXPECT_EQ(fs::file_size(p), header + 5 * (8 + 12 * 7 + 12 * 11) + 8);

  // Surface-only sequences (no nodes) are allowed.
  const Sequence so = make_sequence(2, 0, 4);
  write_sequence((dir_ / "s.fsq").string(), so);
  EXPECT_TRUE(read_sequence((dir_ / "s.fsq").string()).surface == so.surface);
}

TEST_F(SequenceIO, StreamingWriterCommitsOnlyOnCommit) {
  const Sequence s = make_sequence(3, 2, 3);
  const fs::path p = dir_ / "stream.fsq";
  {
    SequenceWriter w(p.string(), s.header);
    for (int f = 0; f < 3; ++f) w.add_frame(s.time[f], s.frame_nodes(f), s.frame_surface(f));
    EXPECT_EQ(w.frames(), 3u);
    EXPECT_FALSE(fs::exists(p)) << "nothing at the final path before commit()";
    w.commit();
    EXPECT_TRUE(fs::exists(p));
    EXPECT_THROW(w.add_frame(10, s.frame_nodes(0), s.frame_surface(0)), Error);
  }
  EXPECT_TRUE(read_sequence(p.string()).nodes == s.nodes);
  EXPECT_TRUE(leftovers("stream.fsq").empty());
}

TEST_F(SequenceIO, WriterWithoutCommitLeavesNothing) {
  const Sequence s = make_sequence(2, 2, 3);
  const fs::path p = dir_ / "abandoned.fsq";
  {
    SequenceWriter w(p.string(), s.header);
    w.add_frame(s.time[0], s.frame_nodes(0), s.frame_surface(0));
    EXPECT_EQ(leftovers().size(), 1u) << "the temporary file exists while writing";
  }
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(leftovers().empty());
  // A writer that never got a frame cannot commit, and leaves nothing either.
  {
    SequenceWriter w(p.string(), s.header);
    const std::string msg = error_of([&] { w.commit(); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, "no frames");
  }
  EXPECT_TRUE(leftovers().empty());
}

TEST_F(SequenceIO, NonFiniteFrameIsRejectedAndNothingRemains) {
  Sequence s = make_sequence(3, 4, 5);
  const fs::path p = dir_ / "nan.fsq";
  std::vector<float> bad_nodes(s.frame_nodes(1), s.frame_nodes(1) + 12);
  bad_nodes[7] = std::nanf("");
  std::vector<float> bad_surface(s.frame_surface(1), s.frame_surface(1) + 15);
  bad_surface[14] = std::numeric_limits<float>::infinity();
  struct Case {
    double time;
    const float* nodes;
    const float* surface;
    const char* problem;
  } cases[] = {
      {s.time[1], bad_nodes.data(), s.frame_surface(1), "frame 1: node 2 has a non-finite coordinate"},
      {s.time[1], s.frame_nodes(1), bad_surface.data(), "frame 1: surface vertex 4 has a non-finite coordinate"},
      {std::nan(""), s.frame_nodes(1), s.frame_surface(1), "frame 1: time is nan"},
      {s.time[0], s.frame_nodes(1), s.frame_surface(1), "strictly increasing"},
      {s.time[1], nullptr, s.frame_surface(1), "node positions are missing"},
  };
  for (const Case& c : cases) {
    SequenceWriter w(p.string(), s.header);
    w.add_frame(s.time[0], s.frame_nodes(0), s.frame_surface(0));
    const std::string msg = error_of([&] { w.add_frame(c.time, c.nodes, c.surface); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, c.problem);
    // The writer is still alive, yet its temporary file is already gone.
    EXPECT_TRUE(leftovers().empty()) << c.problem;
    EXPECT_THROW(w.commit(), Error);
    EXPECT_FALSE(fs::exists(p));
  }
}

TEST_F(SequenceIO, BadHeadersAreRejectedByTheWriter) {
  const fs::path p = dir_ / "h.fsq";
  auto msg_for = [&](SequenceHeader h) { return error_of([&] { SequenceWriter w(p.string(), h); }); };
  SequenceHeader h;
  h.num_surface = 3;
  h.units = "mm";
  EXPECT_HAS(msg_for(h), "units are 'mm', expected 'cm'");
  h = SequenceHeader{};
  h.num_surface = 3;
  h.resolution = "medium";
  EXPECT_HAS(msg_for(h), "resolution is 'medium'");
  h.resolution = "low";
  h.fps = 0;
  EXPECT_HAS(msg_for(h), "not in (0, 1000]");
  h.fps = 30;
  h.num_surface = 0;
  EXPECT_HAS(msg_for(h), "neither nodes nor surface");
  EXPECT_TRUE(leftovers().empty());
  // A missing folder is named.
  SequenceHeader ok;
  ok.num_surface = 3;
  const std::string missing = (dir_ / "no_dir" / "x.fsq").string();
  EXPECT_HAS(error_of([&] { SequenceWriter w(missing, ok); }), missing);
}

TEST_F(SequenceIO, TruncatedFileIsRejected) {
  const fs::path p = dir_ / "t.fsq";
  write_sequence(p.string(), make_sequence(4, 3, 5));
  const std::vector<char> full = read_bytes(p);
  for (size_t cut : {full.size() - 1, full.size() - 8, full.size() / 2, size_t(40), size_t(10), size_t(3)}) {
    write_bytes(p, std::vector<char>(full.begin(), full.begin() + cut));
    const std::string msg = error_of([&] { read_sequence(p.string()); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, "truncated");
  }
  std::vector<char> longer = full;
  longer.push_back(0);
  write_bytes(p, longer);
  EXPECT_HAS(error_of([&] { read_sequence(p.string()); }), "unexpected bytes after the checksum");
}

TEST_F(SequenceIO, FlippedByteFailsTheChecksum) {
  const fs::path p = dir_ / "c.fsq";
  write_sequence(p.string(), make_sequence(4, 3, 5));
  std::vector<char> b = read_bytes(p);
  for (size_t at : {b.size() / 2, b.size() - 20, b.size() - 1}) {
    std::vector<char> bad = b;
    bad[at] ^= 0x10;
    write_bytes(p, bad);
    const std::string msg = error_of([&] { read_sequence(p.string()); });
    EXPECT_HAS(msg, p.string());
    EXPECT_HAS(msg, "checksum mismatch");
    EXPECT_HAS(msg, "corrupt");
  }
}

TEST_F(SequenceIO, WrongMagicVersionAndMissingFile) {
  const fs::path p = dir_ / "m.fsq";
  write_sequence(p.string(), make_sequence(1, 1, 1));
  std::vector<char> b = read_bytes(p);
  std::vector<char> bad = b;
  std::memcpy(bad.data(), "FACESRIG", 8);  // a rig file is not a sequence
  write_bytes(p, bad);
  std::string msg = error_of([&] { read_sequence(p.string()); });
  EXPECT_HAS(msg, p.string());
  EXPECT_HAS(msg, "not a facesr sequence file");
  EXPECT_HAS(msg, "FACESRIG");
  bad = b;
  bad[8] = 2;
  write_bytes(p, bad);
  msg = error_of([&] { read_sequence(p.string()); });
  EXPECT_HAS(msg, "unsupported sequence format version 2");
  const std::string missing = (dir_ / "missing.fsq").string();
  msg = error_of([&] { read_sequence(missing); });
  EXPECT_HAS(msg, missing);
}
