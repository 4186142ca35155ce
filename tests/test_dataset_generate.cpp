// facesr dataset: paired LR/HR frames on the procedural head (seconds).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "bench/bench_report.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "dataset/dataset_metrics.h"
#include "dataset/generate.h"
#include "rig/rig_io.h"
#include "test_support.h"

using namespace facesr;
using fixtures::shell_quote;
namespace fs = std::filesystem;

namespace {

class DatasetGenerate : public fixtures::ScratchSuite<DatasetGenerate> {
 public:
  static constexpr const char* kScratch = "facesr_dataset_";

 protected:
  static DatasetOptions tiny() {
    DatasetOptions o;
    o.builtins = {"anger", "pain"};
    o.max_frames = 10;
    o.progress = false;
    return o;
  }
};

TEST_F(DatasetGenerate, TinyDatasetHasPairedFramesManifestAndSplits) {
  const Rig& rig = fixtures::procedural_rig();
  const std::string out = path("tiny");
  const DatasetSummary s = generate_dataset(rig, path("p.rig"), out, tiny());
  EXPECT_EQ(s.sequences, 2);
  EXPECT_EQ(s.frames, 20);
  EXPECT_EQ(s.nan_frames, 0);
  EXPECT_GT(s.hr_mean_step_s, 0);
  EXPECT_GT(s.lr_mean_step_ms, 0);
  EXPECT_GT(s.embedded_error_max_cm, 1e-3) << "the LR lattice should miss some HR motion";
  EXPECT_GE(s.embedded_error_max_cm, s.embedded_error_mean_cm);
  const DatasetManifest m = load_manifest(out + "/manifest.json");
  EXPECT_EQ(m.rig_checksum, rig_checksum(rig));
  ASSERT_EQ(m.sequences.size(), 2u);
  ASSERT_NE(m.find("anger"), nullptr);
  EXPECT_EQ(m.find("anger")->split, "test");
  EXPECT_EQ(m.find("pain")->split, "train");
  EXPECT_TRUE(m.find("pain")->complete);

  const DatasetSequence seq = read_dataset_sequence(out + "/pain.fsd");
  ASSERT_EQ(seq.num_frames(), 10);
  const SimModel lr = make_sim_model(rig, Resolution::Low);
  EXPECT_EQ(seq.header.num_lr_nodes, uint64_t(lr.num_nodes));
  EXPECT_EQ(seq.header.num_surface, uint64_t(rig.num_surface_vertices()));
  // Frame 0 is the neutral face: nothing moved in either simulation.
  double mean, max;
  embedded_error(seq.frame(0), mean, max);
  EXPECT_LT(max, 1e-4);
  for (float v : seq.frame(0).hr_disp) EXPECT_LT(std::abs(v), 1e-4);
  // Later frames move, and the jaw transform is a rotation.
  double moved = 0;
  for (float v : seq.frame(9).hr_disp) moved = std::max(moved, double(std::abs(v)));
  EXPECT_GT(moved, 1e-2);
  const auto& J = seq.frame(9).jaw;
  Mat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = J[3 * i + j];
  EXPECT_NEAR((R * R.transpose() - Mat3::Identity()).norm(), 0, 1e-5);
  EXPECT_FALSE(fs::exists(out + "/pain.fsd.partial"));

  // A second run finds both sequences complete and simulates nothing.
  const DatasetSummary again = generate_dataset(rig, path("p.rig"), out, tiny());
  EXPECT_EQ(again.skipped_sequences, 2);
  EXPECT_DOUBLE_EQ(again.embedded_error_mean_cm, s.embedded_error_mean_cm);

  // An interrupted sequence whose simulator state is lost starts over and
  // reproduces the same frames.
  const DatasetSequence anger = read_dataset_sequence(out + "/anger.fsd");
  fs::remove(out + "/anger.fsd");
  {
    DatasetWriter w(out + "/anger.fsd", anger.header);
    for (int f = 0; f < 3; ++f) w.add_frame(anger.frame(f));
  }  // no commit: the .partial stays, as after a kill
  ASSERT_TRUE(fs::exists(out + "/anger.fsd.partial"));
  generate_dataset(rig, path("p.rig"), out, tiny());
  const DatasetSequence redone = read_dataset_sequence(out + "/anger.fsd");
  ASSERT_EQ(redone.num_frames(), 10);
  for (size_t i = 0; i < redone.frame(9).hr_disp.size(); ++i)
    ASSERT_NEAR(redone.frame(9).hr_disp[i], anger.frame(9).hr_disp[i], 1e-4);
}

TEST_F(DatasetGenerate, AnotherRigsManifestIsRejected) {
  const std::string out = path("other");
  generate_dataset(fixtures::procedural_rig(), path("p.rig"), out, [] {
    DatasetOptions o = tiny();
    o.builtins = {"fear"};
    o.max_frames = 2;
    return o;
  }());
  DatasetManifest m = load_manifest(out + "/manifest.json");
  m.rig_checksum ^= 1;
  save_manifest(out + "/manifest.json", m);
  const std::string e = fixtures::error_of([&] { generate_dataset(fixtures::procedural_rig(), "", out, tiny()); });
  EXPECT_NE(e.find("another rig"), std::string::npos) << e;
}

TEST_F(DatasetGenerate, CliJsonKeysAndErrors) {
  auto r = run("dataset --rig " + q("p.rig") + " --out " + q("cli") + " --builtin fear --frames 4 --json -q --markdown " +
               q("bench.md"));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"frames", "sequences", "hr_mean_step_s", "lr_mean_step_ms", "hr_over_lr_time",
                          "embedded_error_mean_cm", "embedded_error_max_cm"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["frames"], 4);
  EXPECT_EQ(j["units"], "cm");
  {
    // One section per rig and machine, holding the per-sequence table.
    std::ifstream md(path("bench.md"));
    const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
    const std::string tag = "<!-- dataset-" + fixtures::procedural_rig().name + "-" + machine_slug() + ":start -->";
    EXPECT_NE(text.find(tag), std::string::npos) << text;
    EXPECT_NE(text.find("| fear | test | 4 |"), std::string::npos) << text;
  }

  r = run("dataset --rig " + q("p.rig") + " --out " + q("bad1") + " --builtin nosuch -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("nosuch"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("bad1/manifest.json")));

  {
    std::ofstream csv(path("broken.csv"));
    csv << "Timecode,BlendShapeCount,JawOpen\n00:00:00:00.000,1,0.1\n00:00:00:01.000,1,abc\n";
  }
  r = run("dataset --rig " + q("p.rig") + " --out " + q("bad2") + " --performance " + q("broken.csv") + " -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("line 3"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("bad2/broken.fsd")));

  r = run("dataset --rig " + q("missing.rig") + " --out " + q("bad3") + " -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("missing.rig"), std::string::npos) << r.err;
}

TEST_F(DatasetGenerate, RenderDrawsEmbeddedErrorHeatMap) {
  generate_dataset(fixtures::procedural_rig(), path("p.rig"), path("tiny2"), [] {
    DatasetOptions o = tiny();
    o.builtins = {"pain"};
    o.max_frames = 6;
    return o;
  }());
  auto r = run("render --rig " + q("p.rig") + " --dataset " + q("tiny2/pain.fsd") + " --count 3 -o " + q("e.png") +
               " --json -q");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("e.png")));
  EXPECT_EQ(nlohmann::json::parse(r.out)["frames"].size(), 3u);
  r = run("render --rig " + q("p.rig") + " --dataset " + q("tiny2/pain.fsd") + " --frames 99 -o " + q("f.png") + " -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("out of range"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("f.png")));
}

}  // namespace
