// DAME and the normal-angle error: zero for identical meshes, invariant under
// rigid motion, positive for a bent mesh, border edges skipped, oriented
// angles (a ridge turned into a valley), and hand-computed hinge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "eval/dame.h"
#include "eval/dihedral_angles.h"
#include "eval/interior_edges.h"
#include "eval/normal_error.h"
#include "test_support.h"

using namespace facesr;

namespace {

// Two triangles on the x axis edge 0-1, both facing +z: (0, 1, 2) on the +y
// side and (1, 0, 3) on the -y side. Vertex 3 is folded about the x axis by
// `fold` radians (positive: down, away from the normals, making a ridge).
// A third triangle (2, 5, 4) touches the pair only at vertex 2: all its edges
// are border edges.
Points hinge(double fold, double third_tilt = 0) {
  Points V(6, 3);
  V.row(0) << 0, 0, 0;
  V.row(1) << 1, 0, 0;
  V.row(2) << 0.5, 1, 0;
  V.row(3) << 0.5, -std::cos(fold), -std::sin(fold);
  V.row(4) << 0.5, 2, std::sin(third_tilt);
  V.row(5) << 1.5, 1.5, 0;
  return V;
}

Tris hinge_tris() {
  Tris F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 2, 5, 4;
  return F;
}

Mat3 some_rotation() {
  return (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(-1.1, Vec3::UnitY()))
      .toRotationMatrix();
}

Points moved(const Points& V, const Mat3& R, const Vec3& t) {
  Points out(V.rows(), 3);
  for (long i = 0; i < V.rows(); ++i) out.row(i) = (R * V.row(i).transpose() + t).transpose();
  return out;
}

// The procedural face with a smooth 3 mm bump on the cheek side: a bent mesh.
Points bumped(const Rig& rig) {
  Points V = rig.surface;
  Vec3 lo, hi;
  bounding_box(V, lo, hi);
  const Vec3 c = 0.5 * (lo + hi) + Vec3(0.25 * (hi.x() - lo.x()), 0, 0);
  const double r = 0.2 * (hi - lo).norm();
  const Points N = vertex_normals(V, rig.surface_tris);
  for (long i = 0; i < V.rows(); ++i) {
    const double d2 = (Vec3(V.row(i)) - c).squaredNorm();
    V.row(i) += 0.3 * std::exp(-d2 / (r * r)) * N.row(i);
  }
  return V;
}

}  // namespace

TEST(EvalDame, HingeHasOneInteriorEdgeAndSevenBorderEdges) {
  const InteriorEdges e = interior_edges(hinge_tris(), 6);
  ASSERT_EQ(e.size(), 1);
  EXPECT_EQ(e.border, 7);
  EXPECT_EQ(e.non_manifold, 0);
  EXPECT_EQ(e.flipped, 0);
  EXPECT_EQ(e.quads[0], (std::array<int32_t, 4>{0, 1, 2, 3}));
}

TEST(EvalDame, OrientedAngleIsPositiveOnARidgeAndNegativeInAValley) {
  const InteriorEdges e = interior_edges(hinge_tris(), 6);
  EXPECT_NEAR(oriented_dihedral_angles(hinge(0), e)[0], 0, 1e-15);
  EXPECT_NEAR(oriented_dihedral_angles(hinge(0.3), e)[0], 0.3, 1e-12);
  EXPECT_NEAR(oriented_dihedral_angles(hinge(-0.3), e)[0], -0.3, 1e-12);
  EXPECT_NEAR(oriented_dihedral_angles(hinge(2.5), e)[0], 2.5, 1e-12);
}

TEST(EvalDame, HingeFoldByHand) {
  const Tris F = hinge_tris();
  // Flat against folded by 0.3 rad: one interior edge, so the area weights
  // cancel and DAME is that edge's masked angle difference.
  EXPECT_NEAR(dame(hinge(0), hinge(0.3), F, {0.0}), 0.3, 1e-12);  // no masking
  EXPECT_NEAR(dame(hinge(0), hinge(0.3), F, {0.2}), 0.3 / (1 + 0.3 / 0.2), 1e-12);
  // Ridge of 0.3 against a valley of 0.3: oriented angles differ by 0.6.
  EXPECT_NEAR(dame(hinge(0.3), hinge(-0.3), F, {0.0}), 0.6, 1e-12);
  // Symmetric in its two meshes.
  EXPECT_NEAR(dame(hinge(0.3), hinge(0), F), dame(hinge(0), hinge(0.3), F), 1e-15);
}

TEST(EvalDame, BorderEdgesAreSkipped) {
  const Tris F = hinge_tris();
  // Tilting the third triangle changes nothing but border edges' neighbourhoods.
  EXPECT_EQ(dame(hinge(0), hinge(0, 0.9), F), 0);
  EXPECT_NEAR(dame(hinge(0), hinge(0.3, 0.9), F, {0.0}), 0.3, 1e-12);
  // A lone triangle has no interior edge at all.
  Tris one(1, 3);
  one << 0, 1, 2;
  EXPECT_EQ(dame(hinge(0), hinge(0.5, 0.5), one), 0);
}

TEST(EvalDame, NonManifoldAndFlippedEdgesAreCounted) {
  Tris F(4, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4, 2, 5, 4;  // edge 0-1 in three triangles
  EXPECT_EQ(interior_edges(F, 6).non_manifold, 1);
  Tris G(2, 3);
  G << 0, 1, 2, 0, 1, 3;  // both traverse 0 -> 1
  const InteriorEdges g = interior_edges(G, 6);
  EXPECT_EQ(g.flipped, 1);
  EXPECT_EQ(g.size(), 0);
  Tris bad(1, 3);
  bad << 0, 1, 9;
  EXPECT_NE(fixtures::error_of([&] { interior_edges(bad, 6); }).find("vertex 9"), std::string::npos);
}

TEST(EvalDame, ZeroForIdenticalMeshes) {
  const Rig& rig = fixtures::procedural_rig();
  EXPECT_EQ(dame(rig.surface, rig.surface, rig.surface_tris), 0);
  EXPECT_EQ(mean_normal_angle_deg(rig.surface, rig.surface, rig.surface_tris), 0);
}

TEST(EvalDame, InvariantUnderRigidMotionAndPositiveWhenBent) {
  const Rig& rig = fixtures::procedural_rig();
  const InteriorEdges e = interior_edges(rig.surface_tris, rig.surface.rows());
  ASSERT_GT(e.size(), 1000);
  const Points test = bumped(rig);
  const double d = dame(rig.surface, test, e);
  EXPECT_GT(d, 1e-4);
  const Mat3 R = some_rotation();
  const Vec3 t(3, -7, 11);
  // The test mesh moved, and both moved.
  EXPECT_NEAR(dame(rig.surface, moved(test, R, t), e), d, 1e-10);
  EXPECT_NEAR(dame(moved(rig.surface, R, t), moved(test, R, t), e), d, 1e-10);
  // A rigidly moved copy is not distorted at all.
  EXPECT_NEAR(dame(rig.surface, moved(rig.surface, R, t), e), 0, 1e-10);
  // A bigger bump is a bigger error.
  Points twice = rig.surface + 2 * (test - rig.surface);
  EXPECT_GT(dame(rig.surface, twice, e), 1.5 * d);
}

TEST(EvalDame, MeshesOfDifferentSizeAreAnError) {
  const Points a = hinge(0);
  const Points b = a.topRows(5);
  EXPECT_NE(fixtures::error_of([&] { dame(a, b, hinge_tris()); }).find("vertices"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { mean_normal_angle_deg(a, b, hinge_tris()); }).find("vertices"), std::string::npos);
}

TEST(EvalDame, NormalAngleOfARotatedTriangle) {
  Points V(3, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 1, 0;
  Tris F(1, 3);
  F << 0, 1, 2;
  const double a = 30 * M_PI / 180;
  // About an axis in the triangle's plane the normal turns by the full angle...
  EXPECT_NEAR(
      mean_normal_angle_deg(V, moved(V, Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(), Vec3(1, 2, 3)), F), 30,
      1e-10);
  EXPECT_NEAR(mean_normal_angle_deg(
                  V, moved(V, Eigen::AngleAxisd(a, Vec3(1, 1, 0).normalized()).toRotationMatrix(), Vec3::Zero()), F),
              30, 1e-10);
  // ...about the normal itself it does not turn.
  EXPECT_NEAR(
      mean_normal_angle_deg(V, moved(V, Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(), Vec3::Zero()), F), 0,
      1e-10);
}

TEST(EvalDame, NormalAngleOfTheBentFaceIsSmallAndPositive) {
  const Rig& rig = fixtures::procedural_rig();
  const double deg = mean_normal_angle_deg(rig.surface, bumped(rig), rig.surface_tris);
  EXPECT_GT(deg, 0.01);
  EXPECT_LT(deg, 10);
}
