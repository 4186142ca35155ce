// `facesr perf` and `facesr render` through the real binary: summaries on
// success, and on bad input a non-zero exit whose message names the file,
// with no output file (or temporary) left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "perf/sequence_io.h"
#include "rig/rig_io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;

namespace {

using fixtures::CliResult;
using fixtures::read_text;

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A small dome with three blendshapes (zero deltas); enough for perf and render.
Rig tiny_rig(int n) {
  Rig rig;
  rig.name = "tiny";
  rig.surface.resize(n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -3 + 6.0 * i / (n - 1), y = -3 + 6.0 * j / (n - 1);
      rig.surface.row(j * n + i) << x, y, 2 * std::exp(-(x * x + y * y) / 6);
    }
  rig.surface_tris.resize(2 * (n - 1) * (n - 1), 3);
  for (int j = 0, f = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      rig.surface_tris.row(f++) << a, a + 1, a + n + 1;
      rig.surface_tris.row(f++) << a, a + n + 1, a + n;
    }
  rig.blendshape_names = {"jawOpen", "mouthSmile_L", "mouthSmile_R"};
  rig.blendshape_deltas.assign(3 * size_t(n) * n * 3, 0.0f);
  // save_rig wants both simulation meshes with the surface embedded: one big
  // tet holding everything will do, as these commands never simulate.
  for (SimMesh* m : {&rig.hr, &rig.lr}) {
    m->mesh.X.resize(4, 3);
    m->mesh.X << -10, -10, -10, 10, -10, -10, 0, 10, -10, 0, 0, 10;
    m->mesh.T.resize(1, 4);
    m->mesh.T << 0, 1, 2, 3;
    m->muscle = {-1};
    m->muscle_fraction = {0};
    m->fibre = {0, 0, 1};
    m->surface.tet.assign(size_t(n) * n, 0);
    m->surface.weights.assign(size_t(n) * n * 4, 0.25f);
    m->surface.outside.assign(size_t(n) * n, 0);
  }
  return rig;
}

class PerfRenderCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("facesr_cli_perf_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const Rig rig = tiny_rig(16);
    save_rig(rig, (dir_ / "tiny.rig").string());
    save_rig(tiny_rig(9), (dir_ / "other.rig").string());
    // 8 frames: the dome's top rises by 0.1 cm per frame.
    Sequence s;
    s.header.num_surface = uint64_t(rig.num_surface_vertices());
    s.header.rig_checksum = rig_checksum(rig);
    for (int f = 0; f < 8; ++f) {
      s.time.push_back(f / 30.0);
      for (int v = 0; v < rig.num_surface_vertices(); ++v)
        for (int k = 0; k < 3; ++k)
          s.surface.push_back(float(rig.surface(v, k) + (k == 2 && rig.surface(v, 1) > 0 ? 0.1 * f : 0.0)));
    }
    write_sequence((dir_ / "tiny.fsq").string(), s);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static CliResult run(const std::string& args) { return fixtures::run_cli(args, dir_.string()); }
  static std::string p(const std::string& name) { return quote((dir_ / name).string()); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  // Nothing named `stem` or `stem.tmp...` exists.
  static bool no_output(const std::string& stem) {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().rfind(stem, 0) == 0) return false;
    return true;
  }
  static fs::path dir_;
};
fs::path PerfRenderCli::dir_;

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

}  // namespace

TEST_F(PerfRenderCli, PerfWriteThenShow) {
  CliResult r = run("perf write --rig " + p("tiny.rig") + " --builtin smile -q -o " + p("smile.json"));
  ASSERT_EQ(r.status, 0) << r.err;
  ASSERT_TRUE(fs::exists(path("smile.json")));
  r = run("perf show --rig " + p("tiny.rig") + " --performance " + p("smile.json") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out;
  EXPECT_EQ(j["frames"], 61);
  EXPECT_EQ(j["fps"], 30.0);
  EXPECT_DOUBLE_EQ(j["duration_s"].get<double>(), 2.0);
  EXPECT_EQ(j["max_weight"]["mouthSmile_L"], 1.0);
  EXPECT_FALSE(j["max_weight"].contains("jawOpen"));  // unused shapes are not listed
  r = run("perf show --rig " + p("tiny.rig") + " --builtin talk");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_HAS(r.out, "jawOpen");
  EXPECT_HAS(r.out, "30 fps");
}

TEST_F(PerfRenderCli, PerfErrors) {
  const std::string missing = path("missing.json");
  CliResult r = run("perf show --rig " + p("tiny.rig") + " --performance " + quote(missing) + " --json");
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, missing);
  EXPECT_TRUE(r.out.empty()) << r.out;

  std::ofstream(path("bad.json")) << R"({"format":"facesr-performance","version":1,"fps":30,
    "keyframes":[{"time":0,"weights":{"jawOpen":0}},{"time":1,"weights":{"jawOpen":2}}]})";
  r = run("perf show --rig " + p("tiny.rig") + " --performance " + p("bad.json"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, path("bad.json") + ": keyframe 1: weight 'jawOpen' is 2, outside [0, 1]");

  r = run("perf show --rig " + p("tiny.rig"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "exactly one of --performance");

  r = run("perf write --rig " + p("tiny.rig") + " --builtin grin -o " + p("grin.json"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "unknown built-in performance 'grin'");
  EXPECT_HAS(r.err, "smile");
  EXPECT_TRUE(no_output("grin.json"));

  r = run("perf write --rig " + p("missing.rig") + " --builtin smile -o " + p("m.json"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, path("missing.rig"));
  EXPECT_TRUE(no_output("m.json"));

  r = run("perf write --rig " + p("tiny.rig") + " --builtin smile -o " + p("no_dir/x.json"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "does not exist");
}

TEST_F(PerfRenderCli, RenderWritesPngAndJsonSummary) {
  const CliResult r = run("render --rig " + p("tiny.rig") + " --seq " + p("tiny.fsq") + " --count 3 --heat --gltf " +
                          p("tiny.gltf") + " -o " + p("tiny.png") + " --json -q");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;  // -q
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out;
  EXPECT_EQ(j["png"], path("tiny.png"));
  EXPECT_EQ(j["frames"], nlohmann::json({0, 4, 7}));
  EXPECT_EQ(j["units"], "cm");
  EXPECT_NEAR(j["max_displacement_cm"].get<double>(), 0.7, 1e-5);
  ASSERT_TRUE(fs::exists(path("tiny.png")));
  // PNG header: width and height are the big-endian u32s at offsets 16 and 20.
  const std::string png = read_text(path("tiny.png"));
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
           (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
  };
  EXPECT_EQ(be32(16), j["width"].get<uint32_t>());
  EXPECT_EQ(be32(20), j["height"].get<uint32_t>());
  const nlohmann::json g = nlohmann::json::parse(read_text(path("tiny.gltf")));
  EXPECT_EQ(g["meshes"][0]["primitives"][0]["targets"].size(), 7u);

  const CliResult f =
      run("render --rig " + p("tiny.rig") + " --seq " + p("tiny.fsq") + " --frames 1,6 -o " + p("two.png") + " --json");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_EQ(nlohmann::json::parse(f.out)["frames"], nlohmann::json({1, 6}));
  EXPECT_HAS(f.err, "[render]");  // progress on stderr without -q
}

TEST_F(PerfRenderCli, RenderErrors) {
  const std::string missing = path("missing.fsq");
  CliResult r = run("render --rig " + p("tiny.rig") + " --seq " + quote(missing) + " -o " + p("r1.png") + " --json");
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "facesr: error:");
  EXPECT_HAS(r.err, missing);
  EXPECT_TRUE(r.out.empty());
  EXPECT_TRUE(no_output("r1.png"));

  r = run("render --rig " + p("missing.rig") + " --seq " + p("tiny.fsq") + " -o " + p("r2.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, path("missing.rig"));
  EXPECT_TRUE(no_output("r2.png"));

  r = run("render --rig " + p("tiny.rig") + " --seq " + p("tiny.fsq") + " --frames 0,8 -o " + p("r3.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, path("tiny.fsq") + ": frame 8 is out of range");
  EXPECT_TRUE(no_output("r3.png"));

  r = run("render --rig " + p("tiny.rig") + " --seq " + p("tiny.fsq") + " --frames 0,x -o " + p("r4.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "'x' is not a frame index");
  EXPECT_TRUE(no_output("r4.png"));

  r = run("render --rig " + p("other.rig") + " --seq " + p("tiny.fsq") + " -o " + p("r5.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "256 surface vertices but rig " + path("other.rig") + " has 81");
  EXPECT_TRUE(no_output("r5.png"));

  // A damaged sequence: cut in half.
  fs::copy_file(path("tiny.fsq"), path("cut.fsq"), fs::copy_options::overwrite_existing);
  fs::resize_file(path("cut.fsq"), fs::file_size(path("cut.fsq")) / 2);
  r = run("render --rig " + p("tiny.rig") + " --seq " + p("cut.fsq") + " -o " + p("r6.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, path("cut.fsq") + ": truncated");
  EXPECT_TRUE(no_output("r6.png"));

  r = run("render --rig " + p("tiny.rig") + " --seq " + p("tiny.fsq") + " --frames 1 --count 2 -o " + p("r7.png"));
  EXPECT_NE(r.status, 0);
  EXPECT_TRUE(no_output("r7.png"));
  r = run("render --rig " + p("tiny.rig") + " --seq " + p("tiny.fsq") + " -o " + p("no_dir/r8.png"));
  EXPECT_EQ(r.status, 1);
  EXPECT_HAS(r.err, "does not exist");
}
