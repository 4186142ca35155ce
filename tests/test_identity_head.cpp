// Heads from the ICT identity modes (facesr head identity), the jaw hinge
// fit they once broke, and the real take that diverged on such a head.
// Tests needing ../shared skip with a message when it is absent.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "mesh/obj_io.h"
#include "rig/identity_head.h"
#include "rig/jaw_fit.h"
#include "rig/rig_io.h"
#include "test_support.h"

using namespace facesr;
namespace fs = std::filesystem;

namespace {

std::string shared_data(const std::string& sub) {
  if (const char* e = std::getenv("FACESR_SHARED_DIR")) return std::string(e) + "/data/" + sub;
  return fs::path(fixtures::ict_dir()).parent_path().string() + "/" + sub;
}

std::string scratch(const std::string& name) {
  const std::string d = (fs::temp_directory_path() / ("facesr_identity_" + name + "_" + std::to_string(::getpid()))).string();
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(JawHinge, PivotIsOnTheAxisAndNearestTheOriginForAnyRotation) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    Vec3 axis(u(rng), u(rng), u(rng));
    if (trial % 3 == 0) axis = Vec3(1, 1e-10 * u(rng), 3e-10 * u(rng));  // the ICT case: axis along x
    axis.normalize();
    const double angle = (2 + 38 * (u(rng) + 1) / 2) * M_PI / 180;
    const Vec3 true_pivot(5 * u(rng), 5 * u(rng), 5 * u(rng));
    const Mat3 R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Vec3 t = true_pivot - R * true_pivot;
    Vec3 pivot, a;
    double got = 0;
    hinge_from_rigid(R, t, pivot, a, got);
    ASSERT_NEAR(got, angle, 1e-9);
    // On the true axis, and its foot from the origin (no component along it).
    const Vec3 off = (pivot - true_pivot) - (pivot - true_pivot).dot(a) * a;
    ASSERT_LT(off.norm(), 1e-6) << "trial " << trial;
    ASSERT_LT(std::abs(pivot.dot(a)), 1e-6) << "trial " << trial << ": pivot " << pivot.transpose();
    const Vec3 near(1, 2, 3), beside = nearest_on_axis(pivot, a, near);
    ASSERT_LT(std::abs((near - beside).dot(a)), 1e-9);
  }
}

TEST(JawHinge, ARigWithAPivotFarDownTheAxisIsRefusedByName) {
  Rig r = fixtures::procedural_rig();
  r.jaw.pivot += 1e13 * r.jaw.axis;
  const std::string e = fixtures::error_of([&] { validate_rig(r, "old.rig"); });
  EXPECT_NE(e.find("jaw.pivot"), std::string::npos) << e;
  EXPECT_NE(e.find("rebuild the rig"), std::string::npos) << e;
  EXPECT_NO_THROW(validate_rig(fixtures::procedural_rig(), "p.rig"));
}

TEST(IdentityHead, WeightsOfZeroGiveTheGenericHeadAndBadInputWritesNothing) {
  const std::string ids = shared_data("ict-facekit-identities");
  if (!fs::exists(fixtures::ict_dir() + "/generic_neutral_mesh.obj") || !fs::exists(ids + "/identity000.obj"))
    GTEST_SKIP() << "ICT FaceKit data or identity modes not found near " << fixtures::ict_dir();
  EXPECT_EQ(count_identity_modes(ids), 10);
  const std::string d = scratch("zero");
  IdentityHeadSpec spec{fixtures::ict_dir(), ids, {0.0, 0.0}};
  const IdentityHeadReport r = write_identity_head(spec, d + "/h");
  EXPECT_EQ(r.modes, 2);
  EXPECT_EQ(r.expressions, 53);
  EXPECT_DOUBLE_EQ(r.max_offset_cm, 0.0);
  const Points a = read_obj_vertices(fixtures::ict_dir() + "/jawOpen.obj"), b = read_obj_vertices(d + "/h/jawOpen.obj");
  ASSERT_EQ(a.rows(), b.rows());
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-5);  // written with 6 decimals
  // A weight moves the neutral and every expression by the same offset.
  spec.weights = {2.0};
  write_identity_head(spec, d + "/w");
  const Points n0 = read_obj_vertices(fixtures::ict_dir() + "/generic_neutral_mesh.obj");
  const Points n1 = read_obj_vertices(d + "/w/generic_neutral_mesh.obj"), e1 = read_obj_vertices(d + "/w/jawOpen.obj");
  const Points mode = read_obj_vertices(ids + "/identity000.obj");
  EXPECT_LT((n1 - n0 - 2.0 * (mode - n0)).cwiseAbs().maxCoeff(), 2e-5);
  EXPECT_LT(((e1 - n1) - (a - n0)).cwiseAbs().maxCoeff(), 2e-5);
  // More weights than modes, a NaN weight: errors naming them, no folder.
  spec.weights.assign(11, 0.0);
  EXPECT_NE(fixtures::error_of([&] { write_identity_head(spec, d + "/x"); }).find("10 modes"), std::string::npos);
  spec.weights = {std::nan("")};
  EXPECT_NE(fixtures::error_of([&] { write_identity_head(spec, d + "/x"); }).find("not finite"), std::string::npos);
  EXPECT_FALSE(fs::exists(d + "/x"));
  fs::remove_all(d);
}

// Seed 5 (±3σ) is one of the heads on which every frame of a real take
// diverged before the hinge fix (its pivot came out 1.8e13 cm down the
// axis). Its coarse rig must put the pivot by the teeth and play the take.
TEST(IdentityHead, TheHeadThatDivergedPlaysARealTake) {
  const std::string ids = shared_data("ict-facekit-identities");
  const std::string take = shared_data("livelink") + "/MySlate_3_Jason_Millers_iPhone.csv";
  if (!fs::exists(fixtures::ict_dir() + "/generic_neutral_mesh.obj") || !fs::exists(ids + "/identity000.obj") ||
      !fs::exists(take))
    GTEST_SKIP() << "ICT FaceKit data, identity modes or Live Link takes not found near " << fixtures::ict_dir();
  const std::string d = scratch("seed5");
  const auto q = fixtures::shell_quote;
  auto r = fixtures::run_cli("head identity --ict " + q(fixtures::ict_dir()) + " --identities " + q(ids) +
                                 " --seed 5 -o " + q(d + "/head") + " --json",
                             d);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["weights_sigma"].size(), 10u);
  r = fixtures::run_cli("rig build --source " + q(d + "/head") + " --preset coarse -o " + q(d + "/h.rig") + " -q", d);
  ASSERT_EQ(r.status, 0) << r.err;
  fs::remove_all(d + "/head");
  const Rig rig = load_rig(d + "/h.rig");
  const Vec3 teeth = rig.teeth_lower.V.colwise().mean().transpose();
  EXPECT_LT((rig.jaw.pivot - teeth).norm(), 15.0) << "pivot " << rig.jaw.pivot.transpose();
  r = fixtures::run_cli("simulate --rig " + q(d + "/h.rig") + " --res low --performance " + q(take) +
                            " --frames 40 -o " + q(d + "/t.fsq") + " --json -q",
                        d);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["diverged_frames"], 0);
  EXPECT_EQ(j["nan_frames"], 0);
  EXPECT_EQ(j["unconverged_frames"], 0);
  EXPECT_LT(j["max_rel_residual"].get<double>(), 1e-3);
  EXPECT_LT(j["inverted_tets_max"].get<int>(), j["tets"].get<int>() / 50);
  fs::remove_all(d);
}
