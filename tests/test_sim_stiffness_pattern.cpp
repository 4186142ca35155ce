// The assembled stiffness matrix's pattern (sim/stiffness_pattern.h): summing
// each block's sources must give the same matrix as adding every tet's and
// every surface point's blocks straight into a dense matrix.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "sim/block_model.h"
#include "sim/stiffness_pattern.h"

using namespace facesr;

namespace {

int pair_index(int k, int m) {
  const int lo = std::min(k, m), hi = std::max(k, m);
  return lo * (7 - lo) / 2 + hi;
}

}  // namespace

TEST(SimStiffnessPattern, SourcesSumToTheDenseAssembly) {
  const SimModel m = make_block_model(3, 4, 3, 0.5);
  const StiffnessPattern p = make_stiffness_pattern(m);
  const size_t N = m.num_nodes, T = m.num_tets, n = 3 * N;
  ASSERT_EQ(p.row_offset.size(), N + 1);
  ASSERT_FALSE(m.inc_all.vertices.empty());
  ASSERT_GT(std::count(m.node_bone.begin(), m.node_bone.end(), uint8_t(0)), 0);
  ASSERT_LT(std::count(m.node_bone.begin(), m.node_bone.end(), uint8_t(0)), long(N));  // some bone nodes too
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  // Random (non-symmetric, so that a missed transpose shows) tet blocks and
  // surface Hessians.
  std::vector<double> Ke(90 * T), H(9 * m.inc_all.vertices.size());
  for (double& v : Ke) v = u(rng);
  for (double& v : H) v = u(rng);
  const auto free = [&](int v) { return m.node_bone[v] == 0; };
  for (const bool track : {false, true}) {
    SCOPED_TRACE(track ? "track springs" : "surface Hessians");
    std::vector<double> dense(n * n, 0.0);
    for (size_t t = 0; t < T; ++t)
      for (int k = 0; k < 4; ++k)
        for (int q = 0; q < 4; ++q) {
          const int v = m.tets[4 * t + k], w = m.tets[4 * t + q];
          if (!free(v) || !free(w)) continue;
          const double* B = &Ke[90 * t + 9 * pair_index(k, q)];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) dense[(3 * v + i) * n + 3 * w + j] += k <= q ? B[3 * i + j] : B[3 * j + i];
        }
    for (size_t s = 0; s < m.inc_all.vertices.size(); ++s) {
      const int vert = m.inc_all.vertices[s];
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const int v = m.surf_nodes[4 * vert + a], w = m.surf_nodes[4 * vert + b];
          if (!free(v) || !free(w)) continue;
          const double wab = m.surf_weights[4 * vert + a] * m.surf_weights[4 * vert + b];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              dense[(3 * v + i) * n + 3 * w + j] += track ? (i == j ? m.track_k[vert] * wab : 0.0) : wab * H[9 * s + 3 * i + j];
        }
    }
    std::vector<double> assembled(n * n, 0.0);
    size_t nonzero_blocks = 0;
    for (size_t v = 0; v < N; ++v) {
      if (!free(int(v))) {
        EXPECT_EQ(p.row_offset[v], p.row_offset[v + 1]) << "bone node " << v << " has a row";
        EXPECT_EQ(p.diag[v], -1);
        continue;
      }
      ASSERT_GE(p.diag[v], p.row_offset[v]);
      EXPECT_EQ(p.col[p.diag[v]], int(v));
      for (int b = p.row_offset[v]; b < p.row_offset[v + 1]; ++b) {
        if (b > p.row_offset[v]) EXPECT_LT(p.col[b - 1], p.col[b]) << "columns sorted and distinct";
        double A[9] = {0};
        for (int i = p.tet_offset[b]; i < p.tet_offset[b + 1]; ++i) {
          const int ref = p.tet_ref[i], q = ref >> 1;
          const double* B = &Ke[90 * size_t(q / 10) + 9 * (q % 10)];
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) A[3 * r + c] += (ref & 1) ? B[3 * c + r] : B[3 * r + c];
        }
        if (track) {
          for (int d = 0; d < 3; ++d) A[4 * d] += p.track[b];
        } else {
          for (int i = p.surf_offset[b]; i < p.surf_offset[b + 1]; ++i) {
            const int ref = p.surf_ref[i], s = ref >> 4, vert = m.inc_all.vertices[s];
            const double w = m.surf_weights[4 * vert + ((ref >> 2) & 3)] * m.surf_weights[4 * vert + (ref & 3)];
            for (int e = 0; e < 9; ++e) A[e] += w * H[9 * s + e];
          }
        }
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) assembled[(3 * v + r) * n + 3 * p.col[b] + c] += A[3 * r + c];
        ++nonzero_blocks;
      }
    }
    EXPECT_EQ(nonzero_blocks, p.num_blocks());
    double worst = 0;
    for (size_t i = 0; i < n * n; ++i) worst = std::max(worst, std::abs(assembled[i] - dense[i]));
    EXPECT_LT(worst, 1e-12);
  }
}
