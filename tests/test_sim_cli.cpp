// facesr simulate and facesr bench sim, end to end through the binary.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "bench/robustness_bench.h"
#include "perf/sequence_io.h"
#include "rig/rig_io.h"
#include "test_support.h"

using namespace facesr;
using fixtures::shell_quote;
namespace fs = std::filesystem;

namespace {

class SimCli : public fixtures::ScratchSuite<SimCli> {
 public:
  static constexpr const char* kScratch = "facesr_sim_cli_";

 protected:
  static bool exists_with_prefix(const std::string& stem) {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().rfind(stem, 0) == 0) return true;
    return false;
  }
};

}  // namespace

TEST_F(SimCli, SimulateWritesSequenceAndJsonSummary) {
  const auto r = run("simulate --rig " + q("p.rig") + " --res low --builtin smile --frames 8 --out " + q("s.fsq") +
                     " --json -q");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"frames", "mean_step_ms", "p95_step_ms", "mean_newton_iters", "mean_cg_iters",
                          "max_rel_residual", "nan_frames", "inverted_tets_max", "device"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["frames"], 8);
  EXPECT_EQ(j["nan_frames"], 0);
  EXPECT_LE(j["max_rel_residual"].get<double>(), 1e-3);
  EXPECT_EQ(j["units"], "cm");
  const Sequence s = read_sequence(path("s.fsq"));
  EXPECT_EQ(s.frames(), 8);
  EXPECT_EQ(s.header.resolution, "low");
  EXPECT_EQ(s.header.rig_checksum, rig_checksum(fixtures::procedural_rig()));
  EXPECT_EQ(int(s.header.num_surface), fixtures::procedural_rig().num_surface_vertices());
  // The smile ramps up: the last frame's surface differs from the first.
  double moved = 0;
  for (size_t i = 0; i < 3 * s.header.num_surface; ++i)
    moved = std::max(moved, double(std::abs(s.frame_surface(7)[i] - s.frame_surface(0)[i])));
  EXPECT_GT(moved, 0.01);
}

TEST_F(SimCli, SimulateCpuReferenceAndExternalForces) {
  const auto r = run("simulate --rig " + q("p.rig") + " --builtin jaw --frames 3 --cpu --spring mouth_corner_L:1,-0.5,1:50"
                     " --sphere 4,-2,8:1.5:100 --out " + q("c.fsq") + " --json -q");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(nlohmann::json::parse(r.out)["device"].get<std::string>().find("cpu-reference"), std::string::npos);
}

TEST_F(SimCli, BadInputsFailCleanlyAndWriteNothing) {
  struct Case {
    std::string args, expect;
  };
  std::ofstream(path("bad.json")) << R"({"format":"facesr-performance","version":1,"fps":30,
    "keyframes":[{"time":0,"weights":{"jawOpen":1.5}}]})";
  const std::vector<Case> cases = {
      {"--rig " + q("missing.rig") + " --builtin smile", "missing.rig"},
      {"--rig " + q("p.rig") + " --performance " + q("bad.json"), "jawOpen"},
      {"--rig " + q("p.rig") + " --builtin smile --res medium", "medium"},
      {"--rig " + q("p.rig") + " --builtin nosuch", "nosuch"},
      {"--rig " + q("p.rig") + " --builtin smile --spring mouth_corner_L:1,2:3", "x,y,z"},
      {"--rig " + q("p.rig") + " --builtin smile --sphere 0,0,0:-1:5", "radius"},
      {"--rig " + q("p.rig") + " --builtin smile --solver turbo", "turbo"},
      {"--rig " + q("p.rig") + " --builtin smile --device nosuchdevice", "nosuchdevice"},
  };
  for (const auto& c : cases) {
    const auto r = run("simulate " + c.args + " --out " + q("bad_out.fsq") + " -q");
    EXPECT_NE(r.status, 0) << c.args;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(exists_with_prefix("bad_out")) << c.args;
  }
}

TEST_F(SimCli, BenchSimReportsTimingsAndWritesMarkdown) {
  std::ofstream(path("BENCH.md")) << "# Benchmarks\n\nkept text\n";
  const auto r = run("bench sim --rig " + q("p.rig") + " --frames 3 --no-sweep --solver realtime --markdown " +
                     q("BENCH.md") + " --json -q");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"mean_step_ms", "p95_step_ms", "device", "machine", "date", "opencl", "cpu_reference",
                          "opencl_over_cpu", "tets"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_GT(j["opencl"]["product_ms"].get<double>(), 0.0);
  std::ifstream in(path("BENCH.md"));
  const std::string md((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(md.find("kept text"), std::string::npos);
  EXPECT_NE(md.find("LR simulation step"), std::string::npos);
  EXPECT_NE(md.find("bench-sim-realtime"), std::string::npos);
}

TEST_F(SimCli, BenchRobustnessCountsEveryFrameAndResumesFromItsResults) {
  const std::string args = "bench robustness --rig " + q("p.rig") + " --builtins talk --extreme-frames 40 --solver realtime --results " +
                           q("rob") + " --markdown " + q("rob.md") + " --json -q";
  auto r = run(args);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["rigs"], 1);
  EXPECT_EQ(j["diverged_frames"], 0);
  EXPECT_EQ(j["nan_frames"], 0);
  const auto& h = j["heads"][0];
  EXPECT_EQ(h["rig"], "p");
  ASSERT_EQ(h["performances"].size(), 2u);
  EXPECT_EQ(h["performances"][1]["performance"], "extremes");
  EXPECT_EQ(h["performances"][1]["frames"], 40);
  const auto& t = h["total"];
  for (const char* k : {"frames", "unconverged_frames", "recovered_frames", "diverged_frames", "nan_frames",
                        "inverted_tets_max", "max_rel_residual", "mean_step_ms", "p95_step_ms"})
    EXPECT_TRUE(t.contains(k)) << k;
  EXPECT_EQ(t["frames"].get<int>(), h["performances"][0]["frames"].get<int>() + 40);
  EXPECT_NE(fixtures::read_text(path("rob.md")).find("| p |"), std::string::npos);
  // Run again: the rig's result is read back, not recomputed.
  r = run(args);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["heads"][0]["total"], t);
}

TEST(RobustnessFrames, AreSeededFarApartAndInRange) {
  const std::vector<std::string> names = {"jawOpen", "jawLeft", "jawRight", "jawForward", "mouthSmile_L"};
  const Performance a = robustness_extreme_frames(names, 200, 3), b = robustness_extreme_frames(names, 200, 3);
  ASSERT_EQ(a.frames(), 200);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_NE(a.weights, robustness_extreme_frames(names, 200, 4).weights);
  for (float w : a.weights) ASSERT_TRUE(w >= 0 && w <= 1);
  // Every shape alone at full weight comes first, each followed by rest.
  for (size_t s = 0; s < names.size(); ++s) {
    EXPECT_EQ(a.frame(int(2 * s))[s], 1.0f);
    for (size_t k = 0; k < names.size(); ++k) EXPECT_EQ(a.frame(int(2 * s + 1))[k], 0.0f);
  }
  // The four jaw shapes together appear.
  bool all_jaw = false;
  for (int f = 0; f < a.frames(); ++f) all_jaw |= a.frame(f)[0] == 1 && a.frame(f)[1] == 1 && a.frame(f)[2] == 1 && a.frame(f)[3] == 1;
  EXPECT_TRUE(all_jaw);
}
