#include "sr/graph_dijkstra.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>

#include "core/error.h"

namespace facesr {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// (distance, vertex) pairs compare lexicographically, so equal distances pop
// in index order: the search, and every neighbour list built on it, is then
// a function of the graph alone.
using HeapItem = std::pair<double, int32_t>;
using MinHeap = std::priority_queue<HeapItem, std::vector<HeapItem>, std::greater<HeapItem>>;

}  // namespace

EdgeGraph make_edge_graph(const std::vector<std::pair<int, int>>& edges, const Points& X) {
  const int n = int(X.rows());
  EdgeGraph g;
  g.offset.assign(size_t(n) + 1, 0);
  for (const auto& [a, b] : edges) {
    require(a >= 0 && a < n && b >= 0 && b < n,
            "edge graph: edge (" + std::to_string(a) + ", " + std::to_string(b) + ") out of range for " +
                std::to_string(n) + " vertices");
    require(a != b, "edge graph: self-loop at vertex " + std::to_string(a));
    ++g.offset[size_t(a) + 1];
    ++g.offset[size_t(b) + 1];
  }
  for (int v = 0; v < n; ++v) g.offset[size_t(v) + 1] += g.offset[size_t(v)];
  g.target.resize(size_t(g.offset.back()));
  g.length.resize(g.target.size());
  std::vector<int32_t> fill(g.offset.begin(), g.offset.end() - 1);
  for (const auto& [a, b] : edges) {
    const double len = (X.row(a) - X.row(b)).norm();
    require(std::isfinite(len), "edge graph: non-finite position at edge (" + std::to_string(a) + ", " +
                                    std::to_string(b) + ")");
    g.target[size_t(fill[size_t(a)])] = b;
    g.length[size_t(fill[size_t(a)]++)] = len;
    g.target[size_t(fill[size_t(b)])] = a;
    g.length[size_t(fill[size_t(b)]++)] = len;
  }
  return g;
}

std::vector<std::pair<int, int>> tet_unique_edges(const Tets& T) {
  static constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  std::vector<std::pair<int, int>> e;
  e.reserve(size_t(T.rows()) * 6);
  for (long t = 0; t < T.rows(); ++t)
    for (const auto& p : kPairs) {
      const int a = T(t, p[0]), b = T(t, p[1]);
      e.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

void DijkstraScratch::reset(int num_vertices) {
  if (int(dist.size()) != num_vertices) {
    dist.assign(size_t(num_vertices), kInf);
    done.assign(size_t(num_vertices), 0);
    touched.clear();
    return;
  }
  for (int32_t v : touched) {
    dist[size_t(v)] = kInf;
    done[size_t(v)] = 0;
  }
  touched.clear();
}

std::vector<GraphNeighbour> dijkstra_nearest(const EdgeGraph& g, int source, int k,
                                             const std::vector<uint8_t>& is_target, bool skip_source,
                                             DijkstraScratch& s) {
  const int n = g.num_vertices();
  require(source >= 0 && source < n, "dijkstra: source " + std::to_string(source) + " out of range for " +
                                         std::to_string(n) + " vertices");
  require(is_target.empty() || int(is_target.size()) == n, "dijkstra: target mask has " +
                                                               std::to_string(is_target.size()) + " entries for " +
                                                               std::to_string(n) + " vertices");
  std::vector<GraphNeighbour> out;
  if (k <= 0) return out;
  out.reserve(size_t(k));
  s.reset(n);
  MinHeap heap;
  s.dist[size_t(source)] = 0;
  s.touched.push_back(source);
  heap.emplace(0.0, source);
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (s.done[size_t(v)]) continue;
    s.done[size_t(v)] = 1;
    if (!(skip_source && v == source) && (is_target.empty() || is_target[size_t(v)])) {
      out.push_back({v, d});
      if (int(out.size()) == k) break;
    }
    for (int32_t e = g.offset[size_t(v)]; e < g.offset[size_t(v) + 1]; ++e) {
      const int32_t w = g.target[size_t(e)];
      const double nd = d + g.length[size_t(e)];
      if (nd < s.dist[size_t(w)]) {
        if (s.dist[size_t(w)] == kInf) s.touched.push_back(w);
        s.dist[size_t(w)] = nd;
        heap.emplace(nd, w);
      }
    }
  }
  return out;
}

std::vector<double> dijkstra_distances(const EdgeGraph& g, int source) {
  const int n = g.num_vertices();
  require(source >= 0 && source < n, "dijkstra: source " + std::to_string(source) + " out of range for " +
                                         std::to_string(n) + " vertices");
  std::vector<double> dist(size_t(n), kInf);
  std::vector<uint8_t> done(size_t(n), 0);
  MinHeap heap;
  dist[size_t(source)] = 0;
  heap.emplace(0.0, source);
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (done[size_t(v)]) continue;
    done[size_t(v)] = 1;
    for (int32_t e = g.offset[size_t(v)]; e < g.offset[size_t(v) + 1]; ++e) {
      const int32_t w = g.target[size_t(e)];
      const double nd = d + g.length[size_t(e)];
      if (nd < dist[size_t(w)]) {
        dist[size_t(w)] = nd;
        heap.emplace(nd, w);
      }
    }
  }
  return dist;
}

}  // namespace facesr
