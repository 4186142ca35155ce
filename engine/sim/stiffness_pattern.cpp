#include "sim/stiffness_pattern.h"

#include <algorithm>
#include <map>

#include "core/error.h"

namespace facesr {

StiffnessPattern make_stiffness_pattern(const SimModel& m) {
  const size_t N = m.num_nodes, T = m.num_tets;
  const auto free = [&](int32_t v) { return m.node_bone[v] == 0; };
  // Per row, column → (tet refs, surface refs); std::map keeps the columns sorted.
  struct Sources {
    std::vector<int32_t> tet, surf;
    double track = 0;
  };
  std::vector<std::map<int32_t, Sources>> rows(N);
  for (size_t t = 0; t < T; ++t)
    for (int k = 0; k < 4; ++k)
      for (int q = 0; q < 4; ++q) {
        const int32_t v = m.tets[4 * t + k], u = m.tets[4 * t + q];
        if (!free(v) || !free(u)) continue;
        const int lo = std::min(k, q), hi = std::max(k, q);
        const int pair = lo * (7 - lo) / 2 + hi;
        rows[v][u].tet.push_back(int32_t(2 * (10 * t + pair) + (k > q ? 1 : 0)));
      }
  const auto& verts = m.inc_all.vertices;
  for (size_t i = 0; i < verts.size(); ++i) {
    const int32_t s = verts[i];
    const double kt = m.track_k[s];
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const int32_t v = m.surf_nodes[4 * s + a], u = m.surf_nodes[4 * s + b];
        if (!free(v) || !free(u)) continue;
        Sources& src = rows[v][u];
        src.surf.push_back(int32_t(16 * i + 4 * a + b));
        if (kt > 0) src.track += kt * m.surf_weights[4 * s + a] * m.surf_weights[4 * s + b];
      }
  }
  StiffnessPattern p;
  p.row_offset.assign(N + 1, 0);
  p.diag.assign(N, -1);
  p.tet_offset.push_back(0);
  p.surf_offset.push_back(0);
  for (size_t v = 0; v < N; ++v) {
    for (const auto& [u, src] : rows[v]) {
      if (size_t(u) == v) p.diag[v] = int32_t(p.col.size());
      p.col.push_back(u);
      p.tet_ref.insert(p.tet_ref.end(), src.tet.begin(), src.tet.end());
      p.tet_offset.push_back(int32_t(p.tet_ref.size()));
      p.surf_ref.insert(p.surf_ref.end(), src.surf.begin(), src.surf.end());
      p.surf_offset.push_back(int32_t(p.surf_ref.size()));
      p.track.push_back(src.track);
    }
    p.row_offset[v + 1] = int32_t(p.col.size());
    // A free node in no tet would have a zero row: the solver could not move it.
    if (free(int32_t(v)) && p.diag[v] < 0) throw Error("stiffness pattern: free node " + std::to_string(v) + " is in no tet");
  }
  return p;
}

}  // namespace facesr
