#include "sr/sr_geometry.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "sr/graph_dijkstra.h"
#include "sr/linear_assignment.h"

namespace facesr {

namespace {

// Appends to `row` the Euclidean-nearest points of P (by (distance, index))
// to q that `row` does not hold yet and that are not `skip`, until it has k.
void fill_euclidean(const Points& P, const Vec3& q, int k, int skip, std::vector<GraphNeighbour>& row) {
  std::vector<uint8_t> taken(size_t(P.rows()), 0);
  for (const auto& nb : row) taken[size_t(nb.vertex)] = 1;
  if (skip >= 0) taken[size_t(skip)] = 1;
  std::vector<std::pair<double, int32_t>> cand;
  cand.reserve(size_t(P.rows()));
  for (int i = 0; i < P.rows(); ++i)
    if (!taken[size_t(i)]) cand.emplace_back((P.row(i).transpose() - q).norm(), i);
  const size_t need = std::min(cand.size(), size_t(std::max(0, k - int(row.size()))));
  std::partial_sort(cand.begin(), cand.begin() + long(need), cand.end());
  for (size_t c = 0; c < need; ++c) row.push_back({cand[c].second, cand[c].first});
}

void sort_by_distance(std::vector<GraphNeighbour>& row) {
  std::stable_sort(row.begin(), row.end(), [](const GraphNeighbour& a, const GraphNeighbour& b) {
    return a.dist < b.dist;
  });
}

std::vector<float> to_float(const Points& P) {
  std::vector<float> out(size_t(P.rows()) * 3);
  for (long i = 0; i < P.rows(); ++i)
    for (int c = 0; c < 3; ++c) out[size_t(i) * 3 + size_t(c)] = float(P(i, c));
  return out;
}

void require_finite(const Points& P, const std::string& what) {
  for (long i = 0; i < P.rows(); ++i)
    require(P.row(i).allFinite(), "sr geometry: " + what + " row " + std::to_string(i) + " is not finite");
}

}  // namespace

SrGeometry build_sr_geometry(const Rig& rig, const SrGeometryOptions& opt) {
  const Points& X = rig.lr.mesh.X;  // the simulator's LR rest (make_sim_model copies it as is)
  const Points& S = rig.surface;
  const Points& S_lr = rig.predeform.surface_predeformed.rows() == S.rows() ? rig.predeform.surface_predeformed : S;
  const int N = int(X.rows()), M = int(S.rows());
  require(N > 0, "sr geometry: the rig has no LR nodes");
  require(M > 0, "sr geometry: the rig has no face surface");
  require(rig.lr.mesh.T.rows() > 0, "sr geometry: the rig's LR mesh has no tets");
  require(rig.surface_tris.rows() > 0, "sr geometry: the rig's face surface has no triangles");
  require(opt.graph_k >= 1 && opt.graph_k <= N - 1, "sr geometry: graph_k = " + std::to_string(opt.graph_k) +
                                                        " is outside [1, " + std::to_string(N - 1) + "]");
  const int kmax = std::min(N, 64);
  require(opt.upsample_k >= 1 && opt.upsample_k <= kmax, "sr geometry: upsample_k = " +
                                                             std::to_string(opt.upsample_k) + " is outside [1, " +
                                                             std::to_string(kmax) + "]");
  require_finite(X, "LR rest node");
  require_finite(S, "HR rest vertex");
  require_finite(S_lr, "HR vertex in the LR frame");

  SrGeometry g;
  g.num_lr = N;
  g.num_hr = M;
  g.graph_k = opt.graph_k;
  g.upsample_k = opt.upsample_k;
  g.lr_rest = to_float(X);
  g.hr_rest = to_float(S);
  g.hr_rest_lr_frame = to_float(S_lr);
  g.hr_tris.assign(rig.surface_tris.data(), rig.surface_tris.data() + rig.surface_tris.size());
  // A rig without an LR embedding of its surface (only synthetic test rigs)
  // leaves these empty; the embedded skip then refuses the geometry.
  if (rig.lr.surface.tet.size() == size_t(M) && rig.lr.surface.weights.size() == 4 * size_t(M)) {
    g.embed_nodes.resize(4 * size_t(M));
    g.embed_weights.assign(rig.lr.surface.weights.begin(), rig.lr.surface.weights.end());
    for (int v = 0; v < M; ++v)
      for (int k = 0; k < 4; ++k) g.embed_nodes[4 * size_t(v) + k] = rig.lr.mesh.T(rig.lr.surface.tet[size_t(v)], k);
  }

  // §3.1: first EdgeConv graph, geodesic along the LR tet edges.
  {
    const EdgeGraph lr_graph = make_edge_graph(tet_unique_edges(rig.lr.mesh.T), X);
    const int k = opt.graph_k;
    g.lr_graph.assign(size_t(N) * size_t(k), -1);
    const std::vector<uint8_t> all;
#pragma omp parallel
    {
      DijkstraScratch scratch;
#pragma omp for schedule(dynamic, 64)
      for (int i = 0; i < N; ++i) {
        std::vector<GraphNeighbour> row = dijkstra_nearest(lr_graph, i, k, all, true, scratch);
        if (int(row.size()) < k) {
          fill_euclidean(X, X.row(i).transpose(), k, i, row);
          sort_by_distance(row);
        }
        for (int s = 0; s < k; ++s) g.lr_graph[size_t(i) * size_t(k) + size_t(s)] = row[size_t(s)].vertex;
      }
    }
  }

  // §3.2: one-to-one LR node → HR vertex map of least total distance.
  {
    std::vector<double> cost(size_t(N) * size_t(M));
#pragma omp parallel for schedule(static)
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < M; ++j) cost[size_t(i) * size_t(M) + size_t(j)] = (X.row(i) - S_lr.row(j)).norm();
    g.lr_to_hr = linear_assignment_any(cost.data(), N, M);
  }

  // §3.2: per HR vertex the nearest mapped nodes along the surface edges.
  {
    std::vector<int32_t> hr_to_lr(size_t(M), -1);
    for (int i = 0; i < N; ++i)
      if (g.lr_to_hr[size_t(i)] >= 0) hr_to_lr[size_t(g.lr_to_hr[size_t(i)])] = i;
    std::vector<uint8_t> mapped(static_cast<size_t>(M));
    for (int j = 0; j < M; ++j) mapped[size_t(j)] = hr_to_lr[size_t(j)] >= 0;
    const EdgeGraph surf = make_edge_graph(unique_edges(rig.surface_tris), S);
    const int k = opt.upsample_k;
    const size_t slots = size_t(M) * size_t(k);
    g.up_index.assign(slots, -1);
    g.up_dist.assign(slots, 0.f);
    g.up_is_euclid.assign(slots, 0);
#pragma omp parallel
    {
      DijkstraScratch scratch;
#pragma omp for schedule(dynamic, 64)
      for (int j = 0; j < M; ++j) {
        std::vector<GraphNeighbour> row = dijkstra_nearest(surf, j, k, mapped, false, scratch);
        for (auto& nb : row) nb.vertex = hr_to_lr[size_t(nb.vertex)];
        const size_t found = row.size();
        if (int(found) < k) {
          fill_euclidean(X, S_lr.row(j).transpose(), k, -1, row);
          sort_by_distance(row);
        }
        for (int s = 0; s < k; ++s) {
          const size_t at = size_t(j) * size_t(k) + size_t(s);
          g.up_index[at] = row[size_t(s)].vertex;
          g.up_dist[at] = float(row[size_t(s)].dist);
        }
        if (int(found) < k) {
          // The search ran out of its component, so it settled all of it: a
          // slot is a fill-in exactly when its node's mapped vertex (if any)
          // was not settled.
          for (int s = 0; s < k; ++s) {
            const int32_t hv = g.lr_to_hr[size_t(g.up_index[size_t(j) * size_t(k) + size_t(s)])];
            g.up_is_euclid[size_t(j) * size_t(k) + size_t(s)] = hv >= 0 && scratch.done[size_t(hv)] ? 0 : 1;
          }
        }
      }
    }
  }

  // Ablation neighbours: Euclidean, LR frame.
  {
    const int k = opt.upsample_k;
    g.euclid_index.assign(size_t(M) * size_t(k), -1);
    g.euclid_dist.assign(size_t(M) * size_t(k), 0.f);
#pragma omp parallel
    {
      std::vector<std::pair<double, int32_t>> cand(static_cast<size_t>(N));
#pragma omp for schedule(static)
      for (int j = 0; j < M; ++j) {
        const Vec3 q = S_lr.row(j).transpose();
        for (int i = 0; i < N; ++i) cand[size_t(i)] = {(X.row(i).transpose() - q).squaredNorm(), i};
        std::partial_sort(cand.begin(), cand.begin() + k, cand.end());
        for (int s = 0; s < k; ++s) {
          const size_t at = size_t(j) * size_t(k) + size_t(s);
          g.euclid_index[at] = cand[size_t(s)].second;
          g.euclid_dist[at] = float(std::sqrt(cand[size_t(s)].first));
        }
      }
    }
  }
  return g;
}

void validate_sr_geometry(const SrGeometry& g, const std::string& what) {
  const auto fail_if = [&](bool bad, const std::string& field, const std::string& msg) {
    require(!bad, what + ": " + field + " " + msg);
  };
  const size_t N = size_t(std::max(g.num_lr, 0)), M = size_t(std::max(g.num_hr, 0));
  fail_if(g.num_lr <= 0, "num_lr", "is " + std::to_string(g.num_lr) + ", expected > 0");
  fail_if(g.num_hr <= 0, "num_hr", "is " + std::to_string(g.num_hr) + ", expected > 0");
  fail_if(g.graph_k < 1 || g.graph_k > g.num_lr - 1, "graph_k", "= " + std::to_string(g.graph_k) + " is out of range");
  fail_if(g.upsample_k < 1 || g.upsample_k > std::min(g.num_lr, 64), "upsample_k",
          "= " + std::to_string(g.upsample_k) + " is out of range");
  const size_t gk = size_t(g.graph_k), uk = size_t(g.upsample_k);
  const auto size_is = [&](size_t have, size_t want, const std::string& field) {
    fail_if(have != want, field, "has " + std::to_string(have) + " entries, expected " + std::to_string(want));
  };
  size_is(g.lr_rest.size(), 3 * N, "lr_rest");
  size_is(g.hr_rest.size(), 3 * M, "hr_rest");
  size_is(g.lr_graph.size(), N * gk, "lr_graph");
  size_is(g.lr_to_hr.size(), N, "lr_to_hr");
  size_is(g.up_index.size(), M * uk, "up_index");
  size_is(g.up_dist.size(), M * uk, "up_dist");
  size_is(g.euclid_index.size(), M * uk, "euclid_index");
  size_is(g.euclid_dist.size(), M * uk, "euclid_dist");
  if (!g.hr_rest_lr_frame.empty()) size_is(g.hr_rest_lr_frame.size(), 3 * M, "hr_rest_lr_frame");
  if (!g.up_is_euclid.empty()) size_is(g.up_is_euclid.size(), M * uk, "up_is_euclid");
  fail_if(g.hr_tris.size() % 3 != 0, "hr_tris", "size " + std::to_string(g.hr_tris.size()) + " is not a multiple of 3");

  const auto all_finite = [&](const std::vector<float>& v, const std::string& field) {
    for (size_t k = 0; k < v.size(); ++k)
      fail_if(!std::isfinite(v[k]), field, "entry " + std::to_string(k) + " is not finite");
  };
  all_finite(g.lr_rest, "lr_rest");
  all_finite(g.hr_rest, "hr_rest");
  all_finite(g.hr_rest_lr_frame, "hr_rest_lr_frame");
  const auto in_range = [&](const std::vector<int32_t>& v, size_t n, bool allow_minus1, const std::string& field) {
    for (size_t k = 0; k < v.size(); ++k)
      fail_if(!((v[k] >= 0 && size_t(v[k]) < n) || (allow_minus1 && v[k] == -1)), field,
              "entry " + std::to_string(k) + " = " + std::to_string(v[k]) + " is out of range");
  };
  in_range(g.lr_graph, N, false, "lr_graph");
  in_range(g.lr_to_hr, M, true, "lr_to_hr");
  in_range(g.up_index, N, false, "up_index");
  in_range(g.euclid_index, N, false, "euclid_index");
  in_range(g.hr_tris, M, false, "hr_tris");
  std::vector<uint8_t> used(M, 0);
  for (size_t i = 0; i < N; ++i) {
    const int32_t j = g.lr_to_hr[i];
    if (j < 0) continue;
    fail_if(used[size_t(j)] != 0, "lr_to_hr", "maps two LR nodes to HR vertex " + std::to_string(j));
    used[size_t(j)] = 1;
  }
  const auto distances = [&](const std::vector<float>& d, const std::string& field) {
    for (size_t k = 0; k < d.size(); ++k)
      fail_if(!(std::isfinite(d[k]) && d[k] >= 0), field, "entry " + std::to_string(k) + " is not a distance");
  };
  distances(g.up_dist, "up_dist");
  distances(g.euclid_dist, "euclid_dist");
}

}  // namespace facesr
