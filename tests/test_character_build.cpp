// `facesr character build`: the budget recipe, bad input refused before any
// long work, and a run killed mid-way that the same command resumes to a
// complete package.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "character/character_recipe.h"
#include "rig/rig_io.h"
#include "sr/sr_model.h"
#include "test_support.h"

namespace facesr {
namespace {

namespace fs = std::filesystem;
using fixtures::error_of;

#define EXPECT_HAS(msg, part) EXPECT_NE(std::string(msg).find(part), std::string::npos) << (msg)

TEST(CharacterRecipe, DurationsParseWithUnitsAndBadOnesAreRefused) {
  EXPECT_DOUBLE_EQ(parse_duration_s("3h"), 10800);
  EXPECT_DOUBLE_EQ(parse_duration_s("90m"), 5400);
  EXPECT_DOUBLE_EQ(parse_duration_s("45s"), 45);
  EXPECT_DOUBLE_EQ(parse_duration_s("1.5h"), 5400);
  EXPECT_DOUBLE_EQ(parse_duration_s("600"), 600);
  for (const char* bad : {"", "h", "3x", "-1h", "0", "nanm", "3 h"})
    EXPECT_HAS(error_of([&] { parse_duration_s(bad); }), "is not a positive number");
}

TEST(CharacterRecipe, TheBudgetIsSharedOutWholeAndTheTakesFitTheirShare) {
  const CharacterBudget b = split_budget(1000);
  EXPECT_NEAR(b.dataset_s + b.train_a_s + b.train_b_s + b.finish_s, 1000, 1e-9);
  EXPECT_GT(b.finish_s, 0);
  auto frames = [](const std::string&) { return 100; };
  // 10 s per frame, 3000 s: three takes of 100 frames.
  const auto three = plan_training_performances(3000, 10, frames);
  ASSERT_EQ(three.size(), 3u);
  const auto order = character_training_order();
  for (size_t i = 0; i < three.size(); ++i) EXPECT_EQ(three[i], order[i]);
  EXPECT_EQ(three[2], "nudge") << "the near-rest take comes early: the correctives are fitted on it";
  // Never fewer than the paper's two, however small the budget.
  const auto two = plan_training_performances(1, 10, frames);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0], "amazement");
  EXPECT_EQ(two[1], "pain");
  // A huge budget takes every take once.
  EXPECT_EQ(plan_training_performances(1e12, 10, frames).size(), order.size());
  for (const auto& t : character_test_performances())
    EXPECT_EQ(std::count(order.begin(), order.end(), t), 0) << t << " is a test take";
}

class CharacterCli : public fixtures::ScratchSuite<CharacterCli> {
 public:
  static constexpr const char* kScratch = "facesr_character_";
};

TEST_F(CharacterCli, BadHeadsAndSettingsFailBeforeAnyWork) {
  const auto none = run("character build --source " + q("no_such_head") + " -o " + q("o1") + " --budget 1m");
  EXPECT_NE(none.status, 0);
  EXPECT_HAS(none.err, "no_such_head");
  EXPECT_FALSE(fs::exists(path("o1")));
  const auto budget = run("character build --source procedural -o " + q("o2") + " --budget soon");
  EXPECT_NE(budget.status, 0);
  EXPECT_HAS(budget.err, "duration 'soon'");
  const auto frames = run("character build --source procedural -o " + q("o3") + " --max-frames 4");
  EXPECT_NE(frames.status, 0);
  EXPECT_HAS(frames.err, "leaves no validation frame");
  EXPECT_FALSE(fs::exists(path("o2")));
  EXPECT_FALSE(fs::exists(path("o3")));
  if (!fixtures::have_ict()) GTEST_SKIP() << "no ICT FaceKit data at " << fixtures::ict_dir() << ": head checks skipped";
  // An ICT-layout head with one blendshape missing, and one with another vertex count.
  for (const std::string kind : {"missing", "short"}) {
    const std::string head = path("head_" + kind);
    fs::create_directories(head);
    for (const auto& e : fs::directory_iterator(fixtures::ict_dir()))
      if (e.path().filename() != "jawOpen.obj") fs::create_symlink(e.path(), head + "/" + e.path().filename().string());
    if (kind == "short") std::ofstream(head + "/jawOpen.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const auto r = run("character build --source " + fixtures::shell_quote(head) + " -o " + q("o_" + kind));
    EXPECT_NE(r.status, 0) << kind;
    EXPECT_HAS(r.err, "jawOpen.obj");
    EXPECT_FALSE(fs::exists(path("o_" + kind))) << "nothing may be written for a bad head";
  }
}

TEST_F(CharacterCli, AKilledRunResumesToACompletePackage) {
  const std::string args = "character build --source procedural --preset coarse -o " + q("c") +
                           " --budget 8s --max-frames 3 --validation-every 3 --max-epochs 2 --json";
  // Killed (SIGKILL: no chance to clean up) part-way through.
  const int kill_after_s = 25 * fixtures::time_scale();
  const std::string killed = "timeout -s KILL " + std::to_string(kill_after_s) + " " + fixtures::shell_quote(FACESR_CLI) + " " + args + " >" +
                             q("killed.out") + " 2>" + q("killed.err");
  const int status = std::system(killed.c_str());
  (void)status;  // killed or, on a fast machine, finished: both must resume
  ASSERT_TRUE(fs::exists(path("c/character.json"))) << "the run should have finished a stage within " << kill_after_s << " s";
  const auto before = nlohmann::json::parse(fixtures::read_text(path("c/character.json")));
  ASSERT_TRUE(before["stages"].contains("rig"));
  const auto rig_time = fs::last_write_time(path("c/rig.rig"));
  const bool killed_early = !before["stages"].contains("package");
  // The same command finishes it, reusing what was done.
  const auto r = run(args);
  ASSERT_EQ(r.status, 0) << r.err;
  if (killed_early) EXPECT_HAS(r.err, "done earlier, kept");
  EXPECT_EQ(fs::last_write_time(path("c/rig.rig")), rig_time) << "the rig must not be rebuilt";
  const auto s = nlohmann::json::parse(r.out);
  for (const char* k : {"ours_mean_cm", "embedded_mean_cm", "ours_over_embedded", "frames_ours_beats_embedded",
                        "test_frames", "stages", "stages_s", "machine"})
    EXPECT_TRUE(s.contains(k)) << k;
  EXPECT_EQ(s["units"], "cm");
  EXPECT_EQ(s["stages"]["rig"], before["stages"]["rig"]) << "the rig stage's record is kept as it was";
  EXPECT_EQ(s["test_frames"].get<int>(), 6);
  EXPECT_GT(s["ours_mean_cm"].get<double>(), 0);
  for (const char* f : {"rig.rig", "model.fsm", "preview.png", "anger.gltf", "eval/report.json", "character.json"})
    EXPECT_TRUE(fs::exists(path("c/") + f)) << f;
  // The packaged model runs on the packaged rig.
  const SrModel m = load_sr_model(path("c/model.fsm"));
  EXPECT_EQ(m.rig_checksum, rig_checksum(load_rig(path("c/rig.rig"))));
  EXPECT_TRUE(m.arch.zero_rest);
  // A rerun of a finished build does nothing but report it; other settings are refused.
  const auto again = run(args);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out)["stages"], s["stages"]);
  const auto other = run("character build --source procedural --preset coarse -o " + q("c") + " --budget 9s");
  EXPECT_NE(other.status, 0);
  EXPECT_HAS(other.err, "other settings");
}

TEST_F(CharacterCli, InitFromAModelOfAnotherRigTransfersItAndRecordsItsZeroShotError) {
  // The shipped coarse model, relabelled as belonging to another rig: the
  // pipeline must carry it over (model transfer) before fine-tuning.
  SrModel other = load_sr_model(std::string(FACESR_TEST_SOURCE_DIR) + "/samples/assets/procedural_coarse.fsm");
  other.rig_name = "elsewhere";
  other.rig_checksum ^= 0x5a5a5a5a5a5a5a5aull;
  save_sr_model(path("other.fsm"), other);
  const auto r = run("character build --source procedural --preset coarse -o " + q("t") + " --init-from " +
                     q("other.fsm") + " --budget 6s --max-frames 3 --validation-every 3 --max-epochs 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto s = nlohmann::json::parse(r.out);
  const auto& a = s["stages"]["train_a"];
  ASSERT_TRUE(a.contains("transfer")) << a.dump();
  EXPECT_EQ(a["transfer"]["from_rig"], "elsewhere");
  EXPECT_EQ(a["transfer"]["pe_match_max_cm"].get<double>(), 0) << "same geometry: every node finds itself";
  ASSERT_TRUE(s.contains("zero_shot"));
  EXPECT_GT(s["zero_shot"]["test_cm"].get<double>(), 0);
  EXPECT_TRUE(s.contains("blendshape_mean_cm"));
  EXPECT_EQ(load_sr_model(path("t/model.fsm")).rig_checksum, rig_checksum(load_rig(path("t/rig.rig"))));
}

}  // namespace
}  // namespace facesr
