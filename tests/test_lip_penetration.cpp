// The lip contact metric on planted geometry: two facing lip patches pushed
// through each other by a known amount, and a tooth (a cube) that the jaw
// moves onto a lip.
#include <gtest/gtest.h>

#include "eval/lip_penetration.h"

namespace facesr {
namespace {

// An n × n grid over [0, 1]² at height z; triangles facing +z or -z.
void add_patch(Points& V, Tris& F, std::vector<int>& verts, double z, bool up, int n = 5) {
  const int base = int(V.rows());
  V.conservativeResize(base + n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      V.row(base + j * n + i) << double(i) / (n - 1), double(j) / (n - 1), z;
      verts.push_back(base + j * n + i);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = base + j * n + i, b = a + 1, c = a + n, d = c + 1;
      const long t = F.rows();
      F.conservativeResize(t + 2, 3);
      if (up) F.row(t) << a, b, d, F.row(t + 1) << a, d, c;
      else F.row(t) << a, d, b, F.row(t + 1) << a, c, d;
    }
}

TriMesh cube(const Vec3& lo, double side) {
  TriMesh m;
  m.V.resize(8, 3);
  for (int k = 0; k < 8; ++k) m.V.row(k) = lo + side * Vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  m.F.resize(12, 3);
  // Outward, counter-clockwise seen from outside.
  m.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5;
  return m;
}

const std::array<float, 12> kIdentityJaw{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};

TEST(LipPenetration, FacingLipsPushedThroughEachOtherGiveTheOverlap) {
  Points V(0, 3);
  Tris F(0, 3), upper_tris(0, 3), lower_tris(0, 3);
  LipPenetrationSetup s;
  add_patch(V, upper_tris, s.upper, 0.0, /*up=*/false);  // upper lip faces down
  add_patch(V, lower_tris, s.lower, -0.1, /*up=*/true);  // lower lip faces up, 1 mm below
  s.upper_tris = upper_tris;
  s.lower_tris = lower_tris;
  finish_lip_penetration_setup(s, V);
  const LipPenetration rest = lip_penetration(s, V, kIdentityJaw);
  EXPECT_EQ(rest.lip_cm, 0);
  EXPECT_EQ(rest.lip_vertices, 0);
  // The upper lip 0.15 cm down: 0.05 cm through the lower one, both ways.
  Points X = V;
  for (int v : s.upper) X(v, 2) -= 0.15;
  const LipPenetration p = lip_penetration(s, X, kIdentityJaw);
  EXPECT_NEAR(p.lip_cm, 0.05, 1e-9);
  EXPECT_EQ(p.lip_vertices, 50);
  EXPECT_EQ(p.teeth_cm, 0);
  // Only 0.05 cm down: they touch, nothing goes through.
  X = V;
  for (int v : s.upper) X(v, 2) -= 0.05;
  EXPECT_EQ(lip_penetration(s, X, kIdentityJaw).lip_cm, 0);
}

TEST(LipPenetration, LipsInsideTeethCountTheirDepthAndTheJawCarriesTheLowerTeeth) {
  Points V(0, 3);
  Tris ut(0, 3), lt(0, 3);
  LipPenetrationSetup s;
  add_patch(V, ut, s.upper, 0.0, false);
  add_patch(V, lt, s.lower, -1.0, true);
  s.upper_tris = ut;
  s.lower_tris = lt;
  // Upper tooth: a 0.4 cm cube just above the upper lip's centre vertex (0.5, 0.5, 0).
  s.teeth_upper = cube(Vec3(0.3, 0.3, 0.02), 0.4);
  // Lower tooth: far away at rest; the frame's jaw moves it onto the lower lip.
  s.teeth_lower = cube(Vec3(5.3, 0.3, -0.9), 0.4);
  finish_lip_penetration_setup(s, V);
  EXPECT_EQ(lip_penetration(s, V, kIdentityJaw).teeth_cm, 0);
  Points X = V;
  const int centre = s.upper[12];
  X(centre, 2) += 0.12;  // 0.10 cm into the upper tooth (its bottom face at z = 0.02)
  const LipPenetration p = lip_penetration(s, X, kIdentityJaw);
  EXPECT_NEAR(p.teeth_cm, 0.10, 1e-9);
  EXPECT_EQ(p.teeth_vertices, 1);
  // Jaw translated by (-5, 0, -0.15): the lower tooth spans z in [-1.05, -0.65],
  // so the lower lip's centre (z = -1) is 0.05 cm inside it (nearest face z = -1.05).
  const std::array<float, 12> jaw{1, 0, 0, 0, 1, 0, 0, 0, 1, -5, 0, -0.15f};
  const LipPenetration q = lip_penetration(s, V, jaw);
  EXPECT_NEAR(q.teeth_cm, 0.05, 1e-6);
  EXPECT_GE(q.teeth_vertices, 1);
}

TEST(LipPenetration, ContactsAlreadyThereAtRestAreNotCounted) {
  Points V(0, 3);
  Tris ut(0, 3), lt(0, 3);
  LipPenetrationSetup s;
  add_patch(V, ut, s.upper, -0.12, false);  // the upper lip starts 0.02 cm below the lower one
  add_patch(V, lt, s.lower, -0.1, true);
  s.upper_tris = ut;
  s.lower_tris = lt;
  finish_lip_penetration_setup(s, V);
  EXPECT_EQ(lip_penetration(s, V, kIdentityJaw).lip_cm, 0);
}

}  // namespace
}  // namespace facesr
