#pragma once
// Shortest paths along mesh edges: the "geodesic" distances of the paper
// (§3.1 on the LR tet mesh, §3.2 and appendix A on the HR surface).
#include <cstdint>
#include <utility>
#include <vector>

#include "core/types.h"

namespace facesr {

// Undirected graph in compressed rows; each edge is stored in both
// directions with its Euclidean rest length.
struct EdgeGraph {
  std::vector<int32_t> offset;  // num_vertices + 1
  std::vector<int32_t> target;
  std::vector<double> length;
  int num_vertices() const { return offset.empty() ? 0 : int(offset.size()) - 1; }
};

// Throws Error on an out-of-range or self-loop edge. Duplicate edges are kept
// (they do not change shortest paths).
EdgeGraph make_edge_graph(const std::vector<std::pair<int, int>>& edges, const Points& X);

// Unique undirected edges (i < j) of a tet mesh, sorted.
std::vector<std::pair<int, int>> tet_unique_edges(const Tets& T);

struct GraphNeighbour {
  int32_t vertex;
  double dist;
};

// Reusable per-thread buffers so that many searches on one graph do not
// clear O(V) arrays each time.
class DijkstraScratch {
 public:
  void reset(int num_vertices);
  std::vector<double> dist;
  std::vector<uint8_t> done;
  std::vector<int32_t> touched;
};

// Vertices settle in increasing (distance, index) order; returns the first
// `k` settled vertices v with is_target[v] != 0 (all vertices when is_target
// is empty), skipping the source when `skip_source`. Stops as soon as k are
// found; fewer when the source's component holds fewer.
std::vector<GraphNeighbour> dijkstra_nearest(const EdgeGraph& g, int source, int k,
                                             const std::vector<uint8_t>& is_target, bool skip_source,
                                             DijkstraScratch& scratch);

// Shortest-path distance from `source` to every vertex (infinity where
// unreachable).
std::vector<double> dijkstra_distances(const EdgeGraph& g, int source);

}  // namespace facesr
