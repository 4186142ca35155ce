// The model shipped in samples/assets (scripts/make-procedural-model.sh) must
// keep fitting the rig that scripts/demo.sh builds: the rig builder is
// deterministic, and a model is tied to its rig by checksum. This fails when
// a change to the builder or to the model format leaves the shipped file
// stale, before the demo does.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "rig/rig_io.h"
#include "sr/sr_model.h"
#include "test_support.h"

namespace facesr {
namespace {

namespace fs = std::filesystem;

const std::string kShipped = std::string(FACESR_TEST_SOURCE_DIR) + "/samples/assets/procedural_coarse.fsm";

TEST(ShippedModel, FitsTheCoarseProceduralRigAndPlays) {
  ASSERT_TRUE(fs::exists(kShipped)) << kShipped;
  const fs::path dir = fs::temp_directory_path() / ("facesr_shipped" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string rig_path = (dir / "c.rig").string(), gltf = (dir / "c.gltf").string();
  const auto q = fixtures::shell_quote;
  auto r = fixtures::run_cli("rig build --source procedural --preset coarse -q -o " + q(rig_path), dir.string());
  ASSERT_EQ(r.status, 0) << r.err;

  const Rig rig = load_rig(rig_path);
  const SrModel m = load_sr_model(kShipped);
  EXPECT_EQ(m.rig_checksum, rig_checksum(rig)) << "the shipped model is stale: rerun scripts/make-procedural-model.sh";
  EXPECT_NO_THROW(require_model_matches_rig(m, rig_checksum(rig), int(rig.lr.mesh.X.rows()), rig.num_surface_vertices(),
                                            "shipped model", rig_path));

  r = fixtures::run_cli("play --rig " + q(rig_path) + " --model " + q(kShipped) +
                            " --builtin anger --frames 6 --async -q --json -o " + q(gltf),
                        dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("frames").get<int>(), 6);
  EXPECT_GT(j.at("fps").get<double>(), 0);
  EXPECT_EQ(j.at("units").get<std::string>(), "cm");
  EXPECT_GT(fs::file_size(gltf), 1000u);
  // A bad --lr-precision is named, and nothing is written.
  const std::string none = (dir / "none.gltf").string();
  r = fixtures::run_cli("play --rig " + q(rig_path) + " --model " + q(kShipped) +
                            " --builtin anger --frames 2 -q --lr-precision half -o " + q(none),
                        dir.string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--lr-precision must be auto, double or float, not 'half'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(none));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace facesr
