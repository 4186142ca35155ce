// Collision detection and response for the HR simulation (engine/collide,
// sim/contact.h).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collide/boundary_faces.h"
#include "collide/deforming_scene.h"
#include "collide/mouth_collider.h"
#include "mesh/surface_query.h"
#include "sim/contact.h"
#include "sim/simulator.h"
#include "test_support.h"

namespace facesr {
namespace {

TEST(BoundaryFaces, TwoTetsShareOneFaceAndNormalsPointOut) {
  TetMesh m;
  m.X.resize(5, 3);
  m.X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 3, 1, 2, 3, 4;
  if (tet_signed_volume(m.X.row(1), m.X.row(2), m.X.row(3), m.X.row(4)) < 0) std::swap(m.T(1, 2), m.T(1, 3));
  const Tris F = boundary_faces(m);
  ASSERT_EQ(F.rows(), 6);  // 8 faces, the shared one dropped
  Vec3 centre = Vec3::Zero();
  for (int v = 0; v < 5; ++v) centre += m.X.row(v).transpose() / 5.0;
  for (int f = 0; f < F.rows(); ++f) {
    const Vec3 a = m.X.row(F(f, 0)), b = m.X.row(F(f, 1)), c = m.X.row(F(f, 2));
    EXPECT_GT((b - a).cross(c - a).dot((a + b + c) / 3 - centre), 0) << "face " << f << " points inward";
  }
}

TEST(DeformingScene, ClosestPointRaysAndRefit) {
  Tris F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  std::vector<double> x = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  DeformingScene s(F, 4);
  s.update(x);
  auto h = s.closest(Vec3(0.25, 0.75, 0.5), 10);
  ASSERT_GE(h.tri, 0);
  EXPECT_NEAR(h.dist, 0.5, 1e-12);
  EXPECT_NEAR((h.point - Vec3(0.25, 0.75, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR(s.face_normal(h.tri).z(), 1, 1e-12);
  EXPECT_EQ(s.closest(Vec3(0.25, 0.75, 0.5), 0.4).tri, -1);  // beyond max_dist
  EXPECT_EQ(s.crossings(Vec3(0.3, 0.6, 1), Vec3(0, 0, -1)), 1);
  EXPECT_EQ(s.crossings(Vec3(0.3, 0.6, 1), Vec3(0, 0, 1)), 0);
  const auto hits = s.hits(Vec3(0.3, 0.6, 1), Vec3(0, 0, -1));
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_NEAR(hits[0].first, 1, 1e-6);
  // Skipping the triangle under the point finds the other one.
  const int under = h.tri;
  const auto skip = [](int tri, const void* u) { return tri == *static_cast<const int*>(u); };
  const auto h2 = s.closest(Vec3(0.25, 0.75, 0.5), 10, skip, &under);
  ASSERT_GE(h2.tri, 0);
  EXPECT_NE(h2.tri, under);
  EXPECT_GT(h2.dist, 0.5);
  // Refit: lift the square by 2 cm; queries see the new positions.
  for (int v = 0; v < 4; ++v) x[3 * v + 2] = 2;
  s.update(x);
  EXPECT_NEAR(s.closest(Vec3(0.25, 0.75, 0.5), 10).dist, 1.5, 1e-12);
  EXPECT_EQ(s.crossings(Vec3(0.3, 0.6, 1), Vec3(0, 0, -1)), 0);
  EXPECT_EQ(s.crossings(Vec3(0.3, 0.6, 1), Vec3(0, 0, 1)), 1);
  EXPECT_THROW(s.update(std::vector<double>(5)), Error);
}

TEST(ContactPlanes, GradientAndHessianMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const int n = 6;
  std::vector<double> x(3 * n);
  for (double& v : x) v = U(rng);
  std::vector<ContactPlane> planes;
  for (int i = 0; i < 4; ++i) {
    ContactPlane c;
    c.node = i;
    c.normal = Vec3(U(rng), U(rng), U(rng)).normalized();
    // Nodes 0-2 behind their planes, node 3 in front (inactive).
    const double depth = i < 3 ? 0.2 + 0.1 * i : -0.3;
    c.point = Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]) + depth * c.normal;
    c.stiffness = 10 + i;
    planes.push_back(c);
  }
  std::vector<double> g(3 * n, 0.0);
  contact_gradient(planes, x, g);
  const double h = 1e-6;
  for (size_t k = 0; k < x.size(); ++k) {
    auto xp = x, xm = x;
    xp[k] += h;
    xm[k] -= h;
    EXPECT_NEAR(g[k], (contact_energy(planes, xp) - contact_energy(planes, xm)) / (2 * h), 1e-6) << k;
  }
  std::vector<double> dx(3 * n), y(3 * n, 0.0);
  for (double& v : dx) v = U(rng);
  contact_product(planes, x, dx, y);
  auto xp = x;
  for (size_t k = 0; k < x.size(); ++k) xp[k] += h * dx[k];
  std::vector<double> gp(3 * n, 0.0);
  contact_gradient(planes, xp, gp);
  for (size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(y[k], (gp[k] - g[k]) / h, 1e-5) << k;
  EXPECT_EQ(g[9] + g[10] + g[11], 0.0);  // the inactive plane exerts nothing
  std::vector<double> diag(9 * n, 0.0);
  contact_hessian_diag(planes, x, diag);
  EXPECT_NEAR(diag[0] + diag[4] + diag[8], planes[0].stiffness, 1e-12);  // k n nᵀ has trace k
}

// The HR face-surface vertex (and its node) closest to the upper teeth, with
// the teeth point nearest to it.
struct TeethProbe {
  int vertex = -1;
  Vec3 tooth = Vec3::Zero();
  Vec3 skin = Vec3::Zero();
};
TeethProbe nearest_to_upper_teeth(const Rig& rig, const SimModel& m, const MouthCollider& col) {
  SurfaceQuery teeth(rig.teeth_upper.V, rig.teeth_upper.F);
  std::vector<char> in_region(m.num_nodes, 0);
  for (int n : col.region_nodes()) in_region[n] = 1;
  TeethProbe best;
  double dmin = 1e300;
  for (int v = 0; v < m.num_surface; ++v) {
    // Only vertices that sit on a free collision-region node.
    int node = -1;
    for (int k = 0; k < 4; ++k)
      if (m.surf_weights[4 * v + k] > 0.999) node = m.surf_nodes[4 * v + k];
    if (node < 0 || !in_region[node] || m.node_bone[node]) continue;
    const Vec3 p(&m.surf_rest[3 * size_t(v)]);
    const auto c = teeth.closest(p);
    if (c.dist < dmin) dmin = c.dist, best = {v, c.point, p};
  }
  return best;
}

TEST(MouthCollider, FindsAPlantedPenetrationIntoTheTeeth) {
  const Rig& rig = fixtures::procedural_rig();
  const SimModel m = make_sim_model(rig, Resolution::High);
  MouthCollider col(rig, m);
  EXPECT_GT(col.info().region_nodes, 0);
  const TeethProbe probe = nearest_to_upper_teeth(rig, m, col);
  ASSERT_GE(probe.vertex, 0);
  int node = -1;
  for (int k = 0; k < 4; ++k)
    if (m.surf_weights[4 * probe.vertex + k] > 0.999) node = m.surf_nodes[4 * probe.vertex + k];
  FrameInputs in;
  std::vector<ContactPlane> planes;
  col.detect(m.rest, in, planes);
  for (const auto& c : planes) EXPECT_LE(c.penetration, 0) << "rest pose penetrates at node " << c.node;
  // Push the node 0.1 cm into the tooth, past the closest point.
  const Vec3 dir = (probe.tooth - probe.skin).normalized();
  std::vector<double> x = m.rest;
  const Vec3 planted = probe.tooth + 0.1 * dir;
  for (int k = 0; k < 3; ++k) x[3 * size_t(node) + k] = planted[k];
  col.detect(x, in, planes);
  const ContactPlane* found = nullptr;
  for (const auto& c : planes)
    if (c.node == node) found = &c;
  ASSERT_NE(found, nullptr) << "the planted penetration was not detected";
  EXPECT_EQ(found->kind, kUpperTeeth);
  EXPECT_NEAR(found->penetration, 0.1, 0.03);
  EXPECT_GT(contact_depth(*found, x), 0.07);
  // The lower teeth follow the jaw: moving the jaw 5 cm down takes them away,
  // the upper ones stay.
  in.jaw_t = Vec3(0, -5, 0);
  col.detect(x, in, planes);
  bool still = false;
  for (const auto& c : planes) still = still || (c.node == node && c.kind == kUpperTeeth && c.penetration > 0.05);
  EXPECT_TRUE(still);
}

// A point spring drags a lip vertex 0.4 cm into the upper teeth. Without
// collision handling it goes in; with it the skin stops at the tooth.
TEST(MouthCollider, ResponseRemovesThePenetration) {
  const Rig& rig = fixtures::procedural_rig();
  const SimModel m = make_sim_model(rig, Resolution::High);
  auto col = std::make_shared<MouthCollider>(rig, m);
  const TeethProbe probe = nearest_to_upper_teeth(rig, m, *col);
  ASSERT_GE(probe.vertex, 0);
  Controls c;
  c.weights.assign(m.num_shapes, 0.0f);
  PointSpring s;
  s.vertex = probe.vertex;
  s.target = probe.tooth + 0.4 * (probe.tooth - probe.skin).normalized();
  s.stiffness = 300;
  c.springs.push_back(s);
  auto free_sim = make_cpu_simulator(m, {}, col, false);
  const StepStats a = free_sim->step(c);
  {
    std::vector<double> surf;
    free_sim->surface(surf);
    const Vec3 p(&surf[3 * size_t(probe.vertex)]);
    std::printf("probe gap %.3f cm, vertex moved %.3f cm, now %.3f cm from the target\n",
                (probe.tooth - probe.skin).norm(), (p - probe.skin).norm(), (p - s.target).norm());
  }
  auto sim = make_cpu_simulator(m, {}, col, true);
  const StepStats b = sim->step(c);
  EXPECT_GT(a.max_penetration_cm, 0.1) << "the spring should pull the skin into the tooth without collisions";
  EXPECT_GT(a.contacts, 0);
  EXPECT_LE(b.max_penetration_cm, 0.05);
  EXPECT_TRUE(b.converged);
  EXPECT_GT(b.contacts, 0) << "the skin should rest on the tooth";
}

}  // namespace
}  // namespace facesr
