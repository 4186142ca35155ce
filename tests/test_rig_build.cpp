// Rig builder on the procedural head (coarse preset), plus ICT checks that
// skip when ../shared/data/ict-facekit is absent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "core/binary_io.h"
#include "mesh/tet_locator.h"
#include "rig/ict_head.h"
#include "rig/jaw_fit.h"
#include "rig/rig_build.h"
#include "rig/rig_io.h"
#include "rig/rig_summary.h"
#include "sr/sr_model.h"
#include "test_support.h"

using namespace facesr;

namespace {

using fixtures::face_size;
using fixtures::ict_dir;
using fixtures::procedural_rig;

Vec3 embedded(const TetMesh& m, const Embedding& e, int i) {
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 4; ++k) p += double(e.weights[size_t(i) * 4 + k]) * Vec3(m.X.row(m.T(e.tet[i], k)));
  return p;
}

}  // namespace

TEST(RigBuild, EmbeddingReproducesRestPositions) {
  const Rig& r = procedural_rig();
  const double tol = 1e-6 * face_size(r);
  for (int i = 0; i < r.surface.rows(); ++i) {
    const double ftol = tol;  // 1e-6 of the face size, float weights included
    ASSERT_LT((embedded(r.hr.mesh, r.hr.surface, i) - Vec3(r.surface.row(i))).norm(), ftol) << "HR vertex " << i;
    ASSERT_LT((embedded(r.lr.mesh, r.lr.surface, i) - Vec3(r.predeform.surface_predeformed.row(i))).norm(), ftol)
        << "LR vertex " << i;
  }
}

TEST(RigBuild, LatticeCoversTheFace) {
  const Rig& r = procedural_rig();
  long outside = 0;
  for (uint8_t o : r.lr.surface.outside) outside += o;
  EXPECT_EQ(outside, 0);
  const auto s = rig_summary(r);
  EXPECT_EQ(s["embedded_outside_lr"].get<long>(), 0);
  // Every surface vertex lies in (or on) its LR tet.
  for (int i = 0; i < r.surface.rows(); ++i)
    for (int k = 0; k < 4; ++k) ASSERT_GT(r.lr.surface.weights[size_t(i) * 4 + k], -1e-5f) << "vertex " << i;
  // Lattice tets are regular Kuhn tets: 45..90 degree dihedrals, none inverted.
  EXPECT_NEAR(s["lr_min_dihedral_deg"].get<double>(), 45.0, 1e-6);
  EXPECT_EQ(s["inverted_tets"].get<long>(), 0);
}

TEST(RigBuild, PredeformationSeparatesTheLips) {
  const Rig& r = procedural_rig();
  std::vector<int> upper, lower;
  lip_vertices(r, upper, lower);
  ASSERT_GT(upper.size(), 5u);
  ASSERT_GT(lower.size(), 5u);
  std::set<int> up_tets;
  for (int v : upper) up_tets.insert(r.lr.surface.tet[v]);
  for (int v : lower) EXPECT_EQ(up_tets.count(r.lr.surface.tet[v]), 0u) << "LR tet holds both lips, vertex " << v;
  // Lower-lip vertices move with the jaw; upper ones stay.
  EXPECT_GT((r.predeform.surface_predeformed.row(lower[0]) - r.surface.row(lower[0])).norm(),
            (r.predeform.surface_predeformed.row(upper[0]) - r.surface.row(upper[0])).norm());
}

TEST(RigBuild, JawHingeRecoveredFromTeeth) {
  const Rig& r = procedural_rig();
  // The procedural jawOpen is an 18 degree rotation about +x through (0, -0.5, -0.5).
  EXPECT_NEAR(r.jaw.open_angle_deg, 18.0, 1e-6);
  EXPECT_NEAR(std::abs(r.jaw.axis.x()), 1.0, 1e-9);
  EXPECT_NEAR(r.jaw.pivot.y(), -0.5, 1e-6);
  EXPECT_NEAR(r.jaw.pivot.z(), -0.5, 1e-6);
  EXPECT_LT(r.jaw.hinge_max_error_cm, 1e-6);
  EXPECT_EQ(r.jaw.shapes.size(), 4u);
}

TEST(RigBuild, MusclesFibresAndActivations) {
  const Rig& r = procedural_rig();
  ASSERT_GE(r.muscles.size(), 12u);
  std::vector<int> hr(r.muscles.size(), 0), lr(r.muscles.size(), 0);
  for (const auto* sm : {&r.hr, &r.lr}) {
    for (size_t t = 0; t < sm->muscle.size(); ++t) {
      if (sm->muscle[t] < 0) continue;
      (sm == &r.hr ? hr : lr)[sm->muscle[t]]++;
      const Vec3 f(sm->fibre[3 * t], sm->fibre[3 * t + 1], sm->fibre[3 * t + 2]);
      ASSERT_NEAR(f.norm(), 1.0, 1e-5);
      ASSERT_GT(sm->muscle_fraction[t], 0.0f);
      ASSERT_LE(sm->muscle_fraction[t], 1.0f);
    }
  }
  for (size_t m = 0; m < r.muscles.size(); ++m) {
    EXPECT_GT(hr[m], 0) << r.muscles[m].name << " empty in HR";
    EXPECT_GT(lr[m], 0) << r.muscles[m].name << " empty in LR";
  }
  auto idx = [&](const std::string& n) {
    for (size_t m = 0; m < r.muscles.size(); ++m)
      if (r.muscles[m].name == n) return int(m);
    return -1;
  };
  auto shape = [&](const std::string& n) {
    for (int b = 0; b < r.num_blendshapes(); ++b)
      if (r.blendshape_names[b] == n) return b;
    return -1;
  };
  const int nm = int(r.muscles.size());
  ASSERT_GE(shape("mouthSmile_L"), 0);
  EXPECT_EQ(r.activation[shape("mouthSmile_L") * nm + idx("zygomaticus_major_L")], 1.0f);
  EXPECT_EQ(r.activation[shape("mouthSmile_R") * nm + idx("zygomaticus_major_R")], 1.0f);
  EXPECT_EQ(r.activation[shape("mouthSmile_L") * nm + idx("zygomaticus_major_R")], 0.0f);
  // Zygomaticus major fibres run from the cheekbone down toward the mouth
  // corner: mostly vertical and lateral, not front-back.
  const int zm = idx("zygomaticus_major_L");
  const Vec3 a = r.muscles[zm].curve.row(0), b = r.muscles[zm].curve.row(r.muscles[zm].curve.rows() - 1);
  EXPECT_GT(a.y(), b.y());
  EXPECT_GT(a.x(), b.x());
}

TEST(RigBuild, AttachmentsOnCraniumAndJaw) {
  const Rig& r = procedural_rig();
  for (const auto* sm : {&r.hr, &r.lr}) {
    int jaw = 0, cranium = 0;
    ASSERT_EQ(sm->dirichlet.size(), sm->dirichlet_bone.size());
    for (size_t i = 0; i < sm->dirichlet.size(); ++i) {
      ASSERT_GE(sm->dirichlet[i], 0);
      ASSERT_LT(sm->dirichlet[i], sm->mesh.X.rows());
      (sm->dirichlet_bone[i] ? jaw : cranium)++;
    }
    EXPECT_GT(jaw, 0);
    EXPECT_GT(cranium, 0);
  }
}

TEST(RigBuild, TracksCoverTheSkinArea) {
  const Rig& r = procedural_rig();
  double ahr = 0, alr = 0;
  for (float a : r.hr.track_area) ahr += a;
  for (float a : r.lr.track_area) alr += a;
  EXPECT_GT(ahr, 100.0);  // cm², the procedural face
  EXPECT_NEAR(alr, ahr, 1e-3 * ahr);
  EXPECT_LT(r.lr.tracks.size(), r.hr.tracks.size());
}

TEST(RigBuild, RigFileRoundTripsBitExactly) {
  const Rig& r = procedural_rig();
  const auto dir = std::filesystem::temp_directory_path() / ("facesr_rt_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string a = (dir / "a.rig").string(), b = (dir / "b.rig").string();
  save_rig(r, a);
  const Rig back = load_rig(a);
  save_rig(back, b);
  EXPECT_EQ(read_file_bytes(a), read_file_bytes(b));
  EXPECT_EQ(rig_checksum(r), rig_checksum(back));
  EXPECT_EQ(rig_summary(r).dump(), rig_summary(back).dump());
  std::filesystem::remove_all(dir);
}

TEST(RigIct, JawAxisReproducesLowerTeeth) {
  if (!std::filesystem::exists(ict_dir() + "/generic_neutral_mesh.obj"))
    GTEST_SKIP() << "ICT FaceKit data not found at " << ict_dir() << " (set FACESR_ICT_DIR)";
  const HeadSource src = load_ict_head(ict_dir(), false);
  const Jaw jaw = fit_jaw(src);
  EXPECT_LT(jaw.hinge_max_error_cm, 0.05);
  EXPECT_GT(jaw.open_angle_deg, 5.0);
  for (const auto& s : jaw.shapes) EXPECT_LT(s.fit_rms_cm, 0.05) << s.name;
}

TEST(RigIct, DefaultBuildMeetsTheRigGoals) {
  if (!std::filesystem::exists(ict_dir() + "/generic_neutral_mesh.obj"))
    GTEST_SKIP() << "ICT FaceKit data not found at " << ict_dir() << " (set FACESR_ICT_DIR)";
  RigBuildOptions o;
  o.source = ict_dir();
  o.verbose = false;
  const Rig r = build_rig(o);
  const auto s = rig_summary(r);
  EXPECT_GE(s["hr_over_lr_tets"].get<double>(), 20.0);
  EXPECT_GE(s["hr_tets"].get<long>(), 150000);
  EXPECT_LE(s["hr_tets"].get<long>(), 400000);
  EXPECT_EQ(s["inverted_tets"].get<long>(), 0);
  EXPECT_LT(s["embedded_outside_lr"].get<double>(), 0.01 * s["surface_vertices"].get<double>());
  for (auto& [name, n] : s["muscle_tets_hr_per_muscle"].items()) EXPECT_GT(n.get<long>(), 0) << name;
  for (auto& [name, n] : s["muscle_tets_lr_per_muscle"].items()) EXPECT_GT(n.get<long>(), 0) << name;
  std::vector<int> upper, lower;
  lip_vertices(r, upper, lower);
  std::set<int> up;
  for (int v : upper) up.insert(r.lr.surface.tet[v]);
  for (int v : lower) EXPECT_EQ(up.count(r.lr.surface.tet[v]), 0u);
  const double tol = 1e-6 * face_size(r);
  for (int i = 0; i < r.surface.rows(); ++i)
    ASSERT_LT((embedded(r.hr.mesh, r.hr.surface, i) - Vec3(r.surface.row(i))).norm(), tol);
  // The shipped ICT model is bound to this build by checksum (the demo plays it).
  const SrModel shipped = load_sr_model(std::string(FACESR_TEST_SOURCE_DIR) + "/samples/assets/ict.fsm");
  EXPECT_EQ(shipped.rig_checksum, rig_checksum(r))
      << "samples/assets/ict.fsm is stale for this rig build: retrain it, or `facesr model rebind` it when the "
         "rig's geometry is unchanged";
}
