// `facesr model info`, `zero-rest`, `rebind`, `transfer` and `blend` through the real binary: a
// copy differs from its source only in what the command changes (and says so
// in its training record), and bad input fails with a message and no output
// file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "rig/rig_io.h"
#include "sr/sr_model.h"
#include "test_support.h"

namespace facesr {
namespace {

namespace fs = std::filesystem;

class ModelCli : public fixtures::ScratchSuite<ModelCli> {
 public:
  static constexpr const char* kScratch = "facesr_model_cli_";

 protected:
  static std::string shipped() { return std::string(FACESR_TEST_SOURCE_DIR) + "/samples/assets/procedural_coarse.fsm"; }
};

TEST_F(ModelCli, ZeroRestWritesACopyThatDiffersOnlyInZeroRest) {
  const SrModel src = load_sr_model(shipped());
  ASSERT_FALSE(src.arch.zero_rest) << "the test needs a model without zero_rest";
  const auto r = run("model zero-rest " + fixtures::shell_quote(shipped()) + " -o " + q("zr.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out).at("zero_rest").get<bool>());
  const SrModel out = load_sr_model(path("zr.fsm"));
  EXPECT_TRUE(out.arch.zero_rest);
  EXPECT_TRUE(out.training.at("zero_rest_added_after_training").get<bool>());
  EXPECT_EQ(out.rig_checksum, src.rig_checksum);
  ASSERT_EQ(out.tensors.size(), src.tensors.size());
  for (size_t i = 0; i < src.tensors.size(); ++i) EXPECT_EQ(out.tensors[i].values, src.tensors[i].values) << i;

  const auto info = run("model info " + q("zr.fsm") + " --json");
  ASSERT_EQ(info.status, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j.at("num_hr").get<int>(), src.num_hr);
  EXPECT_TRUE(j.at("zero_rest").get<bool>());

  // Setting it twice is refused, and nothing is written.
  const auto again = run("model zero-rest " + q("zr.fsm") + " -o " + q("zr2.fsm"));
  EXPECT_NE(again.status, 0);
  EXPECT_NE(again.err.find("already set"), std::string::npos) << again.err;
  EXPECT_FALSE(fs::exists(path("zr2.fsm")));
}

TEST_F(ModelCli, RebindCarriesAModelOverToARigWithItsGeometryAndNoOther) {
  const SrModel src = load_sr_model(shipped());
  const Rig& base = fixtures::procedural_rig();
  // Same rest poses, neighbourhoods and embedding, another checksum (a muscle
  // is thicker): the copy is bound to it and its weights are untouched.
  Rig moved = base;
  moved.muscles.at(0).radius *= 1.01;
  save_rig(moved, path("moved.rig"));
  auto r = run("model rebind " + fixtures::shell_quote(shipped()) + " --rig " + q("moved.rig") + " -o " +
               q("moved.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("max_position_cm").get<double>(), 0.0);
  const SrModel out = load_sr_model(path("moved.fsm"));
  EXPECT_EQ(out.rig_checksum, rig_checksum(moved));
  EXPECT_NE(out.rig_checksum, src.rig_checksum);
  const size_t before = src.training.contains("rebound") ? src.training.at("rebound").size() : 0;
  ASSERT_EQ(out.training.at("rebound").size(), before + 1);
  EXPECT_EQ(out.training.at("rebound").back().at("to_checksum").get<std::string>(), j.at("to_checksum").get<std::string>());
  ASSERT_EQ(out.tensors.size(), src.tensors.size());
  for (size_t i = 0; i < src.tensors.size(); ++i) EXPECT_EQ(out.tensors[i].values, src.tensors[i].values) << i;
  EXPECT_EQ(out.geometry.up_index, src.geometry.up_index);

  // Bound already: refused.
  r = run("model rebind " + q("moved.fsm") + " --rig " + q("moved.rig") + " -o " + q("again.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("already bound"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("again.fsm")));

  // A surface vertex 0.01 cm away: the rest poses (or what they decide) differ; refused.
  Rig bent = base;
  bent.surface(0, 0) += 0.01;
  save_rig(bent, path("bent.rig"));
  r = run("model rebind " + fixtures::shell_quote(shipped()) + " --rig " + q("bent.rig") + " -o " + q("bent.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("differ"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("bent.fsm")));

  // Another head: refused by name.
  Rig other = base;
  other.name = "other";
  save_rig(other, path("other.rig"));
  r = run("model rebind " + fixtures::shell_quote(shipped()) + " --rig " + q("other.rig") + " -o " + q("o.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("belongs to rig 'procedural', not 'other'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("o.fsm")));
}

TEST_F(ModelCli, TransferWritesAModelBoundToTheRigAndReportsWhatItRecomputed) {
  const SrModel src = load_sr_model(shipped());
  const auto r = run("model transfer " + fixtures::shell_quote(shipped()) + " --rig " + q("p.rig") + " -o " +
                     q("t.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("to_num_lr").get<int>(), src.num_lr);
  EXPECT_EQ(j.at("pe_match_max_cm").get<double>(), 0) << "onto the rig it was trained on, every node finds itself";
  EXPECT_EQ(j.at("units"), "cm");
  const auto rec = j.at("recomputed").get<std::vector<std::string>>();
  EXPECT_NE(std::find(rec.begin(), rec.end(), "pe_rows"), rec.end());
  EXPECT_NE(std::find(rec.begin(), rec.end(), "up_index"), rec.end());
  const SrModel out = load_sr_model(path("t.fsm"));
  EXPECT_EQ(out.rig_checksum, rig_checksum(fixtures::procedural_rig()));
  for (size_t i = 0; i < src.tensors.size(); ++i) EXPECT_EQ(out.tensors[i].values, src.tensors[i].values) << i;

  // A rig that is not there: an error naming it, and no output.
  const auto bad = run("model transfer " + fixtures::shell_quote(shipped()) + " --rig " + q("none.rig") + " -o " +
                       q("t2.fsm"));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("none.rig"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(path("t2.fsm")));
}

TEST_F(ModelCli, BlendInterpolatesWeightsOfCompatibleModelsOnly) {
  const SrModel a = load_sr_model(shipped());
  SrModel b = a;
  for (auto& t : b.tensors)
    for (size_t k = 0; k < t.values.size(); ++k) t.values[k] += 0.25f * float(k % 7) - 0.5f;
  save_sr_model(path("b.fsm"), b);
  const std::string A = fixtures::shell_quote(shipped());
  auto r = run("model blend " + A + " " + q("b.fsm") + " -t 0.25 -o " + q("mix.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(r.out).at("t").get<double>(), 0.25);
  const SrModel mix = load_sr_model(path("mix.fsm"));
  EXPECT_EQ(mix.rig_checksum, a.rig_checksum);
  EXPECT_DOUBLE_EQ(mix.training.at("blend").at("t").get<double>(), 0.25);
  ASSERT_EQ(mix.tensors.size(), a.tensors.size());
  for (size_t i = 0; i < a.tensors.size(); ++i)
    for (size_t k = 0; k < a.tensors[i].values.size(); k += 13)
      EXPECT_NEAR(mix.tensors[i].values[k], 0.75f * a.tensors[i].values[k] + 0.25f * b.tensors[i].values[k], 1e-6f)
          << a.tensors[i].name << "[" << k << "]";
  // The ends give the sources back exactly.
  for (const char* t : {"0", "1"}) {
    r = run("model blend " + A + " " + q("b.fsm") + " -t " + t + " -o " + q(std::string("end") + t + ".fsm"));
    ASSERT_EQ(r.status, 0) << r.err;
    const SrModel e = load_sr_model(path(std::string("end") + t + ".fsm"));
    const SrModel& src = std::string(t) == "0" ? a : b;
    for (size_t i = 0; i < src.tensors.size(); ++i) EXPECT_EQ(e.tensors[i].values, src.tensors[i].values) << t;
  }

  // Another architecture (zero_rest set), a factor outside [0, 1], another
  // rig's model: refused, and nothing written.
  ASSERT_EQ(run("model zero-rest " + A + " -o " + q("zr.fsm")).status, 0);
  r = run("model blend " + A + " " + q("zr.fsm") + " -o " + q("x1.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("different architectures"), std::string::npos) << r.err;
  r = run("model blend " + A + " " + q("b.fsm") + " -t 1.5 -o " + q("x2.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("not in [0, 1]"), std::string::npos) << r.err;
  SrModel other = a;
  other.rig_checksum ^= 1;
  save_sr_model(path("other.fsm"), other);
  r = run("model blend " + A + " " + q("other.fsm") + " -o " + q("x3.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("different rigs"), std::string::npos) << r.err;
  for (const char* f : {"x1.fsm", "x2.fsm", "x3.fsm"}) EXPECT_FALSE(fs::exists(path(f))) << f;
}

TEST_F(ModelCli, MissingOrCorruptModelsFailWithoutOutput) {
  const auto missing = run("model zero-rest " + q("nope.fsm") + " -o " + q("x.fsm"));
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.err.find("nope.fsm"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(path("x.fsm")));
  fs::copy_file(shipped(), path("cut.fsm"));
  fs::resize_file(path("cut.fsm"), fs::file_size(path("cut.fsm")) / 2);
  const auto cut = run("model info " + q("cut.fsm"));
  EXPECT_NE(cut.status, 0);
  EXPECT_NE(cut.err.find("cut.fsm"), std::string::npos) << cut.err;
}

}  // namespace
}  // namespace facesr
