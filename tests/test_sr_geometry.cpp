// Rest-pose neighbourhoods of the SR network (paper §3.1, §3.2): linear
// assignment against brute force, Dijkstra against known and independent
// distances, and build_sr_geometry on the procedural rig and small
// hand-made rigs.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <set>

#include "baselines/mls.h"
#include "baselines/rbf.h"
#include "mesh/tri_mesh.h"
#include "rig/rig_io.h"
#include "sim/sim_model.h"
#include "sr/graph_dijkstra.h"
#include "sr/linear_assignment.h"
#include "sr/sr_geometry.h"
#include "test_support.h"

using namespace facesr;

namespace {

using fixtures::error_of;
using fixtures::procedural_rig;

constexpr double kInf = std::numeric_limits<double>::infinity();

// Least total cost over every injective row → column map (rows <= cols).
double brute_force_assignment(const std::vector<double>& C, int rows, int cols) {
  double best = kInf;
  std::vector<uint8_t> used(size_t(cols), 0);
  std::function<void(int, double)> go = [&](int r, double sum) {
    if (sum >= best) return;
    if (r == rows) {
      best = sum;
      return;
    }
    for (int c = 0; c < cols; ++c) {
      if (used[size_t(c)]) continue;
      used[size_t(c)] = 1;
      go(r + 1, sum + C[size_t(r) * size_t(cols) + size_t(c)]);
      used[size_t(c)] = 0;
    }
  };
  go(0, 0.0);
  return best;
}

std::vector<double> random_costs(std::mt19937& rng, int rows, int cols, bool ties) {
  std::vector<double> C(size_t(rows) * size_t(cols));
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::uniform_int_distribution<int> small(0, 3);
  for (double& c : C) c = ties ? double(small(rng)) : u(rng);
  return C;
}

// Grid of (n+1)² vertices with unit spacing, each square split along the
// (i, j)-(i+1, j+1) diagonal: the shortest path from (0,0) to (a,b) is
// min(a,b) diagonals plus |a-b| unit steps.
struct GridMesh {
  Points V;
  Tris F;
};
GridMesh grid_mesh(int n) {
  GridMesh g;
  g.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.V.row(j * (n + 1) + i) << i, j, 0;
  g.F.resize(2 * n * n, 3);
  int t = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + (n + 1), d = c + 1;
      g.F.row(t++) << a, b, d;
      g.F.row(t++) << a, d, c;
    }
  return g;
}
double grid_distance(int a, int b) { return std::min(a, b) * std::sqrt(2.0) + std::abs(a - b); }

// A tiny rig: an LR block of Kuhn-split cubes and a surface of `patches`
// separate flat grids above it.
Tets cube_tets(int nx, int ny, int nz, Points& X, double h, const Vec3& o) {
  X.resize((nx + 1) * (ny + 1) * (nz + 1), 3);
  const auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) X.row(id(i, j, k)) = (o + h * Vec3(i, j, k)).transpose();
  std::vector<Vec4i> T;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        int c[8];
        for (int b = 0; b < 8; ++b) c[b] = id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
        // Six tets around the 0-7 diagonal (orientation does not matter here).
        const int paths[6][2] = {{1, 3}, {3, 2}, {2, 6}, {6, 4}, {4, 5}, {5, 1}};
        for (const auto& p : paths) T.emplace_back(c[0], c[p[0]], c[p[1]], c[7]);
      }
  Tets out(long(T.size()), 4);
  for (size_t t = 0; t < T.size(); ++t) out.row(long(t)) = T[t].transpose();
  return out;
}

Rig tiny_rig(int patches, int patch_n, double patch_h) {
  Rig r;
  r.lr.mesh.T = cube_tets(4, 4, 2, r.lr.mesh.X, 1.0, Vec3(0, 0, 0));
  std::vector<Vec3> V;
  std::vector<Vec3i> F;
  for (int p = 0; p < patches; ++p) {
    const GridMesh g = grid_mesh(patch_n);
    const int base = int(V.size());
    for (long v = 0; v < g.V.rows(); ++v) V.push_back(Vec3(2.1 * p, 0.3, 2.05) + patch_h * Vec3(g.V.row(v)));
    for (long t = 0; t < g.F.rows(); ++t) F.push_back(g.F.row(t).transpose() + Vec3i::Constant(base));
  }
  r.surface.resize(long(V.size()), 3);
  for (size_t v = 0; v < V.size(); ++v) r.surface.row(long(v)) = V[v].transpose();
  r.surface_tris.resize(long(F.size()), 3);
  for (size_t t = 0; t < F.size(); ++t) r.surface_tris.row(long(t)) = F[t].transpose();
  return r;
}

const SrGeometry& procedural_geometry() {
  static const SrGeometry g = build_sr_geometry(procedural_rig());
  return g;
}

double dist3(const std::vector<float>& a, int i, const std::vector<float>& b, int j) {
  double s = 0;
  for (int c = 0; c < 3; ++c) {
    const double d = double(a[size_t(i) * 3 + size_t(c)]) - double(b[size_t(j) * 3 + size_t(c)]);
    s += d * d;
  }
  return std::sqrt(s);
}

}  // namespace

// ---------------------------------------------------------------- assignment

TEST(LinearAssignment, OptimalAgainstBruteForce) {
  std::mt19937 rng(7);
  int cases = 0;
  for (int rows = 1; rows <= 6; ++rows)
    for (int cols = rows; cols <= 8; ++cols)
      for (int seed = 0; seed < 12; ++seed) {
        const bool ties = seed % 2 == 1;
        const std::vector<double> C = random_costs(rng, rows, cols, ties);
        double total = -1;
        const std::vector<int32_t> a = linear_assignment(C.data(), rows, cols, &total);
        ASSERT_EQ(int(a.size()), rows);
        std::set<int> used;
        double sum = 0;
        for (int r = 0; r < rows; ++r) {
          ASSERT_GE(a[size_t(r)], 0);
          ASSERT_LT(a[size_t(r)], cols);
          used.insert(a[size_t(r)]);
          sum += C[size_t(r) * size_t(cols) + size_t(a[size_t(r)])];
        }
        ASSERT_EQ(int(used.size()), rows) << "not injective, " << rows << "x" << cols;
        EXPECT_NEAR(total, sum, 1e-12);
        ASSERT_NEAR(sum, brute_force_assignment(C, rows, cols), 1e-9) << rows << "x" << cols << " seed " << seed;
        ++cases;
      }
  EXPECT_GT(cases, 300);
}

TEST(LinearAssignment, MoreRowsThanColumnsAssignsEveryColumn) {
  std::mt19937 rng(11);
  for (int cols = 1; cols <= 5; ++cols)
    for (int rows = cols + 1; rows <= 7; ++rows)
      for (int seed = 0; seed < 8; ++seed) {
        const std::vector<double> C = random_costs(rng, rows, cols, seed % 2 == 1);
        double total = -1;
        const std::vector<int32_t> a = linear_assignment_any(C.data(), rows, cols, &total);
        ASSERT_EQ(int(a.size()), rows);
        std::set<int> used;
        double sum = 0;
        for (int r = 0; r < rows; ++r)
          if (a[size_t(r)] >= 0) {
            used.insert(a[size_t(r)]);
            sum += C[size_t(r) * size_t(cols) + size_t(a[size_t(r)])];
          }
        ASSERT_EQ(int(used.size()), cols);
        EXPECT_EQ(int(std::count(a.begin(), a.end(), -1)), rows - cols);
        EXPECT_NEAR(total, sum, 1e-12);
        std::vector<double> Ct(C.size());
        for (int r = 0; r < rows; ++r)
          for (int c = 0; c < cols; ++c)
            Ct[size_t(c) * size_t(rows) + size_t(r)] = C[size_t(r) * size_t(cols) + size_t(c)];
        ASSERT_NEAR(sum, brute_force_assignment(Ct, cols, rows), 1e-9);
      }
}

TEST(LinearAssignment, DeterministicWithAllTies) {
  // Every assignment costs the same: the answer must still not depend on
  // anything but the matrix.
  const std::vector<double> C(4 * 6, 1.0);
  const auto a = linear_assignment(C.data(), 4, 6);
  EXPECT_EQ(a, linear_assignment(C.data(), 4, 6));
  EXPECT_EQ(std::set<int>(a.begin(), a.end()).size(), 4u);
  EXPECT_TRUE(linear_assignment(nullptr, 0, 3).empty());
}

TEST(LinearAssignment, RejectsBadInput) {
  std::vector<double> C(2 * 3, 1.0);
  EXPECT_NE(error_of([&] { linear_assignment(C.data(), 3, 2); }).find("rows >"), std::string::npos);
  C[4] = std::nan("");
  EXPECT_NE(error_of([&] { linear_assignment(C.data(), 2, 3); }).find("cost(1, 1) is not finite"), std::string::npos);
  C[4] = kInf;
  EXPECT_NE(error_of([&] { linear_assignment_any(C.data(), 3, 2); }).find("not finite"), std::string::npos);
}

TEST(LinearAssignment, GeometricProblemOfIctSizeIsFast) {
  // Random points near two interleaved surfaces, 2,885 × 9,409 like the ICT
  // rig: records the time (the real rig's is reported by SrGeometry tests).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 20.0);
  const int N = 2885, M = 9409;
  std::vector<Vec3> a(N), b(M);
  for (auto& p : a) p = Vec3(u(rng), u(rng), 0.1 * u(rng));
  for (auto& p : b) p = Vec3(u(rng), u(rng), 0.0);
  std::vector<double> C(size_t(N) * M);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < M; ++j) C[size_t(i) * M + size_t(j)] = (a[size_t(i)] - b[size_t(j)]).norm();
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = linear_assignment(C.data(), N, M);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "[ timing ] linear assignment " << N << " x " << M << ": " << s << " s\n";
  EXPECT_EQ(std::set<int>(r.begin(), r.end()).size(), size_t(N));
  EXPECT_LT(s, 60.0);
}

// ------------------------------------------------------------------ Dijkstra

TEST(GraphDijkstra, GridDistancesAreKnown) {
  const int n = 6;
  const GridMesh g = grid_mesh(n);
  const EdgeGraph G = make_edge_graph(unique_edges(g.F), g.V);
  EXPECT_EQ(G.num_vertices(), (n + 1) * (n + 1));
  for (int src : {0, 8, 24}) {
    const int si = src % (n + 1), sj = src / (n + 1);
    const std::vector<double> d = dijkstra_distances(G, src);
    for (int v = 0; v < G.num_vertices(); ++v) {
      const int vi = v % (n + 1), vj = v / (n + 1);
      // Diagonals only go up-right/down-left, so the path needs both signs alike.
      const int di = vi - si, dj = vj - sj;
      const double want =
          (di >= 0) == (dj >= 0) ? grid_distance(std::abs(di), std::abs(dj)) : std::abs(di) + std::abs(dj);
      ASSERT_NEAR(d[size_t(v)], want, 1e-12) << "source " << src << " vertex " << v;
    }
  }
}

TEST(GraphDijkstra, NearestTargetsMatchFullDistances) {
  const int n = 8;
  const GridMesh g = grid_mesh(n);
  const EdgeGraph G = make_edge_graph(unique_edges(g.F), g.V);
  std::mt19937 rng(5);
  std::vector<uint8_t> target(size_t(G.num_vertices()));
  for (auto& t : target) t = rng() % 3 == 0;
  DijkstraScratch scratch;
  for (int src = 0; src < G.num_vertices(); src += 7)
    for (bool skip : {false, true}) {
      const std::vector<double> full = dijkstra_distances(G, src);
      const auto nb = dijkstra_nearest(G, src, 6, target, skip, scratch);
      ASSERT_EQ(nb.size(), 6u);
      std::set<int> got;
      for (size_t s = 0; s < nb.size(); ++s) {
        ASSERT_TRUE(target[size_t(nb[s].vertex)]);
        if (skip) { ASSERT_NE(nb[s].vertex, src); }
        ASSERT_NEAR(nb[s].dist, full[size_t(nb[s].vertex)], 1e-12);
        if (s > 0) { ASSERT_GE(nb[s].dist, nb[s - 1].dist); }
        got.insert(nb[s].vertex);
      }
      for (int v = 0; v < G.num_vertices(); ++v)
        if (target[size_t(v)] && !got.count(v) && !(skip && v == src)) {
          ASSERT_GE(full[size_t(v)], nb.back().dist - 1e-12) << "missed closer target " << v;
        }
    }
}

TEST(GraphDijkstra, MatchesFloydWarshallOnRandomGraphs) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    const int n = 30;
    Points X(n, 3);
    for (int i = 0; i < n; ++i) X.row(i) << u(rng), u(rng), u(rng);
    std::vector<std::pair<int, int>> E;
    for (int e = 0; e < 60; ++e) {
      const int a = int(rng() % n), b = int(rng() % n);
      if (a != b) E.emplace_back(a, b);
    }
    std::vector<double> W(size_t(n) * n, kInf);
    for (int i = 0; i < n; ++i) W[size_t(i) * n + size_t(i)] = 0;
    for (auto [a, b] : E) {
      const double l = (X.row(a) - X.row(b)).norm();
      W[size_t(a) * n + size_t(b)] = std::min(W[size_t(a) * n + size_t(b)], l);
      W[size_t(b) * n + size_t(a)] = W[size_t(a) * n + size_t(b)];
    }
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          W[size_t(i) * n + size_t(j)] =
              std::min(W[size_t(i) * n + size_t(j)], W[size_t(i) * n + size_t(k)] + W[size_t(k) * n + size_t(j)]);
    const EdgeGraph G = make_edge_graph(E, X);
    DijkstraScratch scratch;
    for (int s = 0; s < n; ++s) {
      const auto d = dijkstra_distances(G, s);
      for (int v = 0; v < n; ++v) {
        const double want = W[size_t(s) * n + size_t(v)];
        if (std::isinf(want))
          ASSERT_TRUE(std::isinf(d[size_t(v)]));
        else
          ASSERT_NEAR(d[size_t(v)], want, 1e-12);
      }
      // All-vertex nearest list: every reachable vertex, by (distance, index).
      const auto nb = dijkstra_nearest(G, s, n, {}, false, scratch);
      size_t reachable = 0;
      for (int v = 0; v < n; ++v) reachable += std::isfinite(W[size_t(s) * n + size_t(v)]);
      ASSERT_EQ(nb.size(), reachable);
      EXPECT_EQ(nb.front().vertex, s);
      for (size_t i = 1; i < nb.size(); ++i)
        ASSERT_TRUE(nb[i - 1].dist < nb[i].dist || (nb[i - 1].dist == nb[i].dist && nb[i - 1].vertex < nb[i].vertex));
    }
  }
}

TEST(GraphDijkstra, RejectsBadEdgesAndSources) {
  Points X(3, 3);
  X.setZero();
  EXPECT_NE(error_of([&] { make_edge_graph({{0, 3}}, X); }).find("out of range"), std::string::npos);
  EXPECT_NE(error_of([&] { make_edge_graph({{1, 1}}, X); }).find("self-loop"), std::string::npos);
  const EdgeGraph G = make_edge_graph({{0, 1}}, X);
  DijkstraScratch s;
  EXPECT_NE(error_of([&] { dijkstra_distances(G, 3); }).find("source 3"), std::string::npos);
  EXPECT_NE(error_of([&] { dijkstra_nearest(G, 0, 1, std::vector<uint8_t>(2), false, s); }).find("target mask"),
            std::string::npos);
  // The search stops at its component.
  EXPECT_EQ(dijkstra_nearest(G, 0, 5, {}, false, s).size(), 2u);
  EXPECT_EQ(dijkstra_nearest(G, 2, 5, {}, true, s).size(), 0u);
}

// ---------------------------------------------------------------- SrGeometry

TEST(SrGeometry, SizesRangesAndRestPoses) {
  const Rig& r = procedural_rig();
  const auto t0 = std::chrono::steady_clock::now();
  const SrGeometry g = build_sr_geometry(r);
  std::cout << "[ timing ] build_sr_geometry (procedural, N " << g.num_lr << ", M " << g.num_hr << "): "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
  EXPECT_NO_THROW(validate_sr_geometry(g));
  EXPECT_EQ(g.num_lr, int(r.lr.mesh.X.rows()));
  EXPECT_EQ(g.num_hr, int(r.surface.rows()));
  EXPECT_EQ(g.graph_k, 5);
  EXPECT_EQ(g.upsample_k, 20);
  // The LR rest must be the simulator's (the dataset's lr_disp is relative to it).
  const SimModel sim = make_sim_model(r, Resolution::Low);
  ASSERT_EQ(sim.rest.size(), g.lr_rest.size());
  for (size_t k = 0; k < sim.rest.size(); ++k) ASSERT_FLOAT_EQ(g.lr_rest[k], float(sim.rest[k]));
  for (int j = 0; j < g.num_hr; ++j)
    for (int c = 0; c < 3; ++c) {
      ASSERT_FLOAT_EQ(g.hr_rest[size_t(j) * 3 + size_t(c)], float(r.surface(j, c)));
      ASSERT_FLOAT_EQ(g.hr_rest_lr_frame[size_t(j) * 3 + size_t(c)], float(r.predeform.surface_predeformed(j, c)));
    }
  EXPECT_EQ(g.hr_tris.size(), size_t(r.surface_tris.size()));
}

TEST(SrGeometry, AssignmentIsInjectiveAndLocallyOptimal) {
  const SrGeometry& g = procedural_geometry();
  const int N = g.num_lr, M = g.num_hr;
  std::vector<int> node_of(size_t(M), -1);
  int mapped = 0;
  for (int i = 0; i < N; ++i) {
    const int j = g.lr_to_hr[size_t(i)];
    if (j < 0) continue;
    ASSERT_EQ(node_of[size_t(j)], -1) << "HR vertex " << j << " mapped twice";
    node_of[size_t(j)] = i;
    ++mapped;
  }
  ASSERT_EQ(mapped, std::min(N, M));
  const auto cost = [&](int i, int j) { return dist3(g.lr_rest, i, g.hr_rest_lr_frame, j); };
  // No exchange of two pairs, and no move to a free partner, lowers the total.
  std::mt19937 rng(1);
  for (int trial = 0; trial < 20000; ++trial) {
    const int a = int(rng() % N), b = int(rng() % N);
    const int ja = g.lr_to_hr[size_t(a)], jb = g.lr_to_hr[size_t(b)];
    if (ja >= 0 && jb >= 0) {
      ASSERT_GE(cost(a, jb) + cost(b, ja), cost(a, ja) + cost(b, jb) - 1e-5) << a << " " << b;
    } else if (ja >= 0 && jb < 0) {  // b is free: it must not be closer to ja
      ASSERT_GE(cost(b, ja), cost(a, ja) - 1e-5);
    }
    const int v = int(rng() % M);
    if (node_of[size_t(v)] < 0 && ja >= 0) {  // v is free: a must not prefer it
      ASSERT_GE(cost(a, v), cost(a, ja) - 1e-5);
    }
  }
}

TEST(SrGeometry, LrGraphIsNearestAlongTetEdges) {
  const Rig& r = procedural_rig();
  const SrGeometry& g = procedural_geometry();
  const int k = g.graph_k;
  const EdgeGraph G = make_edge_graph(tet_unique_edges(r.lr.mesh.T), r.lr.mesh.X);
  for (int i = 0; i < g.num_lr; i += 13) {
    const std::vector<double> d = dijkstra_distances(G, i);
    std::set<int> row;
    double last = 0;
    for (int s = 0; s < k; ++s) {
      const int v = g.lr_graph[size_t(i) * k + size_t(s)];
      ASSERT_NE(v, i);
      row.insert(v);
      ASSERT_GE(d[size_t(v)], last - 1e-12);
      last = d[size_t(v)];
    }
    ASSERT_EQ(int(row.size()), k);
    for (int v = 0; v < g.num_lr; ++v)
      if (v != i && !row.count(v)) { ASSERT_GE(d[size_t(v)], last - 1e-12) << "node " << i << " missed " << v; }
    // On the lattice the nearest are edge neighbours, one cell or less away.
    const int first = g.lr_graph[size_t(i) * k];
    EXPECT_LE(dist3(g.lr_rest, i, g.lr_rest, first), r.lattice.cell * (1 + 1e-6));
  }
}

TEST(SrGeometry, UpsamplingNeighboursAreNearestMappedAlongSurface) {
  const Rig& r = procedural_rig();
  const SrGeometry& g = procedural_geometry();
  const int k = g.upsample_k;
  const EdgeGraph S = make_edge_graph(unique_edges(r.surface_tris), r.surface);
  int comps = 0;
  face_components(r.surface_tris, r.surface.rows(), comps);
  for (int j = 0; j < g.num_hr; j += 7) {
    const std::vector<double> d = dijkstra_distances(S, j);
    std::vector<double> mapped_d;
    for (int i = 0; i < g.num_lr; ++i)
      if (g.lr_to_hr[size_t(i)] >= 0) mapped_d.push_back(d[size_t(g.lr_to_hr[size_t(i)])]);
    std::sort(mapped_d.begin(), mapped_d.end());
    std::set<int> row;
    for (int s = 0; s < k; ++s) {
      const size_t at = size_t(j) * k + size_t(s);
      row.insert(g.up_index[at]);
      if (s > 0) { ASSERT_GE(g.up_dist[at], g.up_dist[at - 1]); }
      if (g.up_is_euclid[at]) continue;
      const int mv = g.lr_to_hr[size_t(g.up_index[at])];
      ASSERT_GE(mv, 0);
      ASSERT_NEAR(g.up_dist[at], d[size_t(mv)], 1e-4);
      if (comps == 1) { ASSERT_NEAR(g.up_dist[at], mapped_d[size_t(s)], 1e-4) << "vertex " << j << " slot " << s; }
    }
    ASSERT_EQ(int(row.size()), k) << "repeated neighbour at vertex " << j;
    // A mapped vertex is its own nearest, at distance 0.
    const auto own = std::find(g.lr_to_hr.begin(), g.lr_to_hr.end(), j);
    if (own != g.lr_to_hr.end()) {
      EXPECT_EQ(g.up_index[size_t(j) * k], int(own - g.lr_to_hr.begin()));
      EXPECT_EQ(g.up_dist[size_t(j) * k], 0.f);
    }
  }
  if (comps == 1) { EXPECT_EQ(std::count(g.up_is_euclid.begin(), g.up_is_euclid.end(), 1), 0); }
}

TEST(SrGeometry, EuclideanNeighboursAreNearest) {
  const SrGeometry& g = procedural_geometry();
  const int k = g.upsample_k;
  for (int j = 0; j < g.num_hr; j += 11) {
    std::vector<double> d(size_t(g.num_lr));
    for (int i = 0; i < g.num_lr; ++i) d[size_t(i)] = dist3(g.lr_rest, i, g.hr_rest_lr_frame, j);
    std::vector<double> sorted = d;
    std::sort(sorted.begin(), sorted.end());
    for (int s = 0; s < k; ++s) {
      const size_t at = size_t(j) * k + size_t(s);
      ASSERT_NEAR(g.euclid_dist[at], d[size_t(g.euclid_index[at])], 1e-5);
      ASSERT_NEAR(g.euclid_dist[at], sorted[size_t(s)], 1e-5);
    }
  }
}

TEST(SrGeometry, Deterministic) {
  const SrGeometry a = build_sr_geometry(procedural_rig());
  const SrGeometry& b = procedural_geometry();
  EXPECT_EQ(a.lr_graph, b.lr_graph);
  EXPECT_EQ(a.lr_to_hr, b.lr_to_hr);
  EXPECT_EQ(a.up_index, b.up_index);
  EXPECT_EQ(a.up_dist, b.up_dist);
  EXPECT_EQ(a.euclid_index, b.euclid_index);
  EXPECT_EQ(a.euclid_dist, b.euclid_dist);
}

TEST(SrGeometry, RejectsBadOptionsAndRigs) {
  const Rig& r = procedural_rig();
  const int N = int(r.lr.mesh.X.rows());
  SrGeometryOptions o;
  o.graph_k = 0;
  EXPECT_NE(error_of([&] { build_sr_geometry(r, o); }).find("graph_k = 0"), std::string::npos);
  o.graph_k = N;
  EXPECT_NE(error_of([&] { build_sr_geometry(r, o); }).find("graph_k"), std::string::npos);
  o = {};
  o.upsample_k = 0;
  EXPECT_NE(error_of([&] { build_sr_geometry(r, o); }).find("upsample_k = 0"), std::string::npos);
  o.upsample_k = 65;
  EXPECT_NE(error_of([&] { build_sr_geometry(r, o); }).find("upsample_k = 65"), std::string::npos);
  Rig empty;
  EXPECT_NE(error_of([&] { build_sr_geometry(empty); }).find("no LR nodes"), std::string::npos);
  Rig nan_rig = tiny_rig(1, 3, 0.5);
  nan_rig.surface(2, 1) = std::nan("");
  EXPECT_NE(error_of([&] { build_sr_geometry(nan_rig); }).find("not finite"), std::string::npos);

  SrGeometry g = procedural_geometry();
  g.up_index[5] = g.num_lr;
  EXPECT_NE(error_of([&] { validate_sr_geometry(g); }).find("up_index"), std::string::npos);
  g = procedural_geometry();
  g.lr_graph.pop_back();
  EXPECT_NE(error_of([&] { validate_sr_geometry(g); }).find("lr_graph has"), std::string::npos);
}

TEST(SrGeometry, SmallComponentsAreFilledWithEuclideanNodes) {
  // Three 3×3-vertex patches (9 vertices each) over a 75-node block: N > M,
  // every vertex is mapped, but a patch holds 9 < 12 mapped vertices.
  const Rig r = tiny_rig(3, 2, 0.5);
  SrGeometryOptions o;
  o.graph_k = 4;
  o.upsample_k = 12;
  const SrGeometry g = build_sr_geometry(r, o);
  EXPECT_NO_THROW(validate_sr_geometry(g));
  ASSERT_EQ(g.num_hr, 27);
  EXPECT_EQ(int(std::count(g.lr_to_hr.begin(), g.lr_to_hr.end(), -1)), g.num_lr - g.num_hr);
  for (int j = 0; j < g.num_hr; ++j) {
    std::set<int> row;
    int fills = 0;
    for (int s = 0; s < o.upsample_k; ++s) {
      const size_t at = size_t(j) * o.upsample_k + size_t(s);
      row.insert(g.up_index[at]);
      fills += g.up_is_euclid[at];
      if (s > 0) { ASSERT_GE(g.up_dist[at], g.up_dist[at - 1]); }
      if (g.up_is_euclid[at]) {
        ASSERT_NEAR(g.up_dist[at], dist3(g.lr_rest, g.up_index[at], g.hr_rest_lr_frame, j), 1e-5);
      }
    }
    EXPECT_EQ(int(row.size()), o.upsample_k);
    EXPECT_EQ(fills, o.upsample_k - 9) << "vertex " << j;
  }
  // N ≤ M: a finer single patch over the same block.
  const Rig fine = tiny_rig(1, 12, 0.35);
  const SrGeometry h = build_sr_geometry(fine, o);
  EXPECT_EQ(std::count(h.lr_to_hr.begin(), h.lr_to_hr.end(), -1), 0);
  EXPECT_EQ(std::count(h.up_is_euclid.begin(), h.up_is_euclid.end(), 1), 0);
}

// ------------------------------------------------------- ICT measurements

namespace {

double peak_rss_mb() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return 0;
}

}  // namespace

// Timings on a full-size rig (run by hand):
//   facesr rig build --source ../shared/data/ict-facekit -o /tmp/ict.rig -q
//   FACESR_SR_RIG=/tmp/ict.rig facesr_tests --gtest_also_run_disabled_tests
//     --gtest_filter='SrGeometry.DISABLED_FullRigTimings'
TEST(SrGeometry, DISABLED_FullRigTimings) {
  const char* path = std::getenv("FACESR_SR_RIG");
  if (!path) GTEST_SKIP() << "set FACESR_SR_RIG to a .rig file";
  const Rig r = load_rig(path);
  using clock = std::chrono::steady_clock;
  const auto secs = [](clock::time_point t0) { return std::chrono::duration<double>(clock::now() - t0).count(); };
  auto t0 = clock::now();
  const SrGeometry g = build_sr_geometry(r);
  std::cout << "[ timing ] build_sr_geometry N " << g.num_lr << " M " << g.num_hr << ": " << secs(t0)
            << " s, peak RSS " << peak_rss_mb() << " MB\n";
  EXPECT_NO_THROW(validate_sr_geometry(g));
  {
    const int N = g.num_lr, M = g.num_hr;
    std::vector<double> C(size_t(N) * size_t(M));
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < M; ++j) C[size_t(i) * M + size_t(j)] = dist3(g.lr_rest, i, g.hr_rest_lr_frame, j);
    t0 = clock::now();
    double total = 0;
    linear_assignment_any(C.data(), N, M, &total);
    std::cout << "[ timing ] of which linear assignment: " << secs(t0) << " s, mean distance "
              << total / std::min(N, M) << " cm\n";
  }
  int comps = 0;
  face_components(r.surface_tris, r.surface.rows(), comps);
  std::cout << "[ info ] surface components " << comps << ", Euclidean fill-in slots "
            << std::count(g.up_is_euclid.begin(), g.up_is_euclid.end(), 1) << " of " << g.up_is_euclid.size()
            << ", lattice cell " << r.lattice.cell << " cm\n";
  // A smooth field (0.3 cm, ~20 cm wavelength): the error against it at the
  // HR vertices (LR frame) shows how well each baseline interpolates.
  const auto field = [](const float* x, int c) { return 0.3 * std::sin(0.3 * x[(c + 1) % 3] + c); };
  std::vector<float> lr(size_t(g.num_lr) * 3);
  for (int i = 0; i < g.num_lr; ++i)
    for (int c = 0; c < 3; ++c) lr[size_t(i) * 3 + size_t(c)] = float(field(&g.lr_rest[size_t(i) * 3], c));
  const auto field_error = [&](const std::vector<float>& hr) {
    double sum = 0;
    for (int j = 0; j < g.num_hr; ++j) {
      double e2 = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = hr[size_t(j) * 3 + size_t(c)] - field(&g.hr_rest_lr_frame[size_t(j) * 3], c);
        e2 += d * d;
      }
      sum += std::sqrt(e2);
    }
    return sum / g.num_hr;
  };
  for (const auto& [sigma, mu] : std::vector<std::pair<double, double>>{
           {2.0, 0.0}, {1.0, 1e-1}, {2.0, 1e-2}, {2.0, 1e-1}, {4.0, 1e-1}}) {
    t0 = clock::now();
    const RbfBaseline rbf(g, sigma, mu);
    const double build = secs(t0);
    t0 = clock::now();
    const std::vector<float> hr = rbf.apply(lr);
    const double apply = secs(t0);
    double worst = 0;
    for (int i = 0; i < g.num_lr; ++i)
      if (g.lr_to_hr[size_t(i)] >= 0)
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, double(std::abs(hr[size_t(g.lr_to_hr[size_t(i)]) * 3 + size_t(c)] -
                                                  lr[size_t(i) * 3 + size_t(c)])));
    std::cout << "[ timing ] RBF sigma " << sigma << " mu " << mu << ": build " << build << " s, apply "
              << apply << " s, rcond " << rbf.rcond() << ", stored " << rbf.stored_fraction()
              << ", worst node misfit " << worst << " cm, mean field error " << field_error(hr)
              << " cm, peak RSS " << peak_rss_mb() << " MB\n";
  }
  t0 = clock::now();
  const MlsBaseline mls(g, 2.0);
  const double build = secs(t0);
  t0 = clock::now();
  const std::vector<float> hr = mls.apply(lr);
  const double apply = secs(t0);
  long count[3] = {0, 0, 0};
  for (uint8_t d : mls.degree()) ++count[d];
  double lebesgue = 0;  // largest Σ|a|: how much MLS can amplify noise
  for (size_t r = 0; r < mls.weights().size() / size_t(g.upsample_k); ++r) {
    double s = 0;
    for (int k = 0; k < g.upsample_k; ++k) s += std::abs(mls.weights()[r * size_t(g.upsample_k) + size_t(k)]);
    lebesgue = std::max(lebesgue, s);
  }
  std::cout << "[ timing ] MLS sigma 2: build " << build << " s, apply " << apply << " s, degrees 0/1/2 " << count[0]
            << " / " << count[1] << " / " << count[2] << ", max sum|a| " << lebesgue << ", mean field error "
            << field_error(hr) << " cm\n";
}
