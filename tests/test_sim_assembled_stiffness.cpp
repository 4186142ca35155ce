// The CPU reference's assembled stiffness (sim/assembled_stiffness.h) must
// multiply like the element-form product it replaces in PCG, with every
// term present: muscle and flesh tets, track springs, a point spring and a
// sphere (whose Hessian is not a multiple of the identity), with and
// without the definiteness fix.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "sim/assembled_stiffness.h"
#include "sim/simulator.h"
#include "test_support.h"

using namespace facesr;

TEST(SimAssembledStiffness, ProductEqualsTheElementFormOnFreeNodes) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  ASSERT_GT(std::count(m.node_bone.begin(), m.node_bone.end(), uint8_t(1)), 0);
  Controls c;
  c.weights.assign(m.num_shapes, 0.0f);
  c.weights[0] = 0.8f;
  c.springs.push_back({m.num_surface / 3, Vec3(0.5, -2, 1), 3.0});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> x = m.rest;
  for (double& v : x) v += 0.1 * u(rng);
  std::vector<double> s;
  embed_surface(m, x, s);
  c.spheres.push_back({Vec3(s[60], s[61], s[62] + 0.2), 0.8, 7.0});
  const FrameInputs in = prepare_frame(m, c);
  std::vector<double> alpha = tet_activations(m, in);
  for (size_t t = 0; t < alpha.size(); t += 3) alpha[t] = 0.5;
  AssembledStiffness K = make_assembled_stiffness(m);
  for (const bool fix : {false, true}) {
    SCOPED_TRACE(fix ? "definiteness fix" : "exact Hessian");
    ElementHessian H;
    element_hessian(m, in, alpha, x, fix, H);
    assemble_stiffness(m, H, K);
    for (int trial = 0; trial < 3; ++trial) {
      std::vector<double> dx(x.size()), ref, got;
      for (double& v : dx) v = u(rng);
      // The element form also couples bone columns; the solver never moves
      // bone nodes, so compare with their components zeroed.
      for (int v = 0; v < m.num_nodes; ++v)
        if (m.node_bone[v]) dx[3 * v] = dx[3 * v + 1] = dx[3 * v + 2] = 0;
      hessian_product(m, H, dx, ref);
      stiffness_product(K, dx, got);
      ASSERT_EQ(got.size(), ref.size());
      double scale = 0, worst = 0;
      for (double v : ref) scale = std::max(scale, std::abs(v));
      ASSERT_GT(scale, 0);
      for (int v = 0; v < m.num_nodes; ++v)
        for (int k = 0; k < 3; ++k) {
          const size_t i = 3 * size_t(v) + k;
          if (m.node_bone[v]) {
            EXPECT_EQ(got[i], 0.0) << "bone node " << v;
          } else {
            worst = std::max(worst, std::abs(got[i] - ref[i]));
          }
        }
      EXPECT_LT(worst, 1e-12 * scale);
    }
    // The assembled diagonal blocks are the ones the preconditioner inverts.
    const StiffnessPattern& p = K.pattern;
    for (int v = 0; v < m.num_nodes; ++v) {
      if (m.node_bone[v]) continue;
      for (int e = 0; e < 9; ++e)
        EXPECT_NEAR(K.blocks[9 * size_t(p.diag[v]) + e], H.diag[9 * size_t(v) + e], 1e-10 * (1 + std::abs(H.diag[9 * size_t(v) + e])));
    }
  }
}
