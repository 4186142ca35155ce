#include "eval/interior_edges.h"

#include <algorithm>
#include <string>

#include "core/error.h"

namespace facesr {
namespace {

struct HalfEdge {
  int32_t lo, hi;  // undirected key
  int32_t from, to, opposite, face;
};

}  // namespace

InteriorEdges interior_edges(const Tris& F, long num_vertices) {
  std::vector<HalfEdge> h;
  h.reserve(size_t(F.rows()) * 3);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k)
      if (!(F(f, k) >= 0 && F(f, k) < num_vertices))
        throw Error("interior edges: triangle " + std::to_string(f) + " refers to vertex " + std::to_string(F(f, k)) +
                    " of " + std::to_string(num_vertices));
    if (!(F(f, 0) != F(f, 1) && F(f, 1) != F(f, 2) && F(f, 2) != F(f, 0)))
      throw Error("interior edges: triangle " + std::to_string(f) + " repeats a vertex");
    for (int k = 0; k < 3; ++k) {
      const int32_t a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
      h.push_back({std::min(a, b), std::max(a, b), a, b, c, f});
    }
  }
  std::sort(h.begin(), h.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.face < y.face;
  });
  InteriorEdges out;
  for (size_t s = 0; s < h.size();) {
    size_t e = s;
    while (e < h.size() && h[e].lo == h[s].lo && h[e].hi == h[s].hi) ++e;
    const size_t n = e - s;
    if (n == 1) {
      ++out.border;
    } else if (n > 2) {
      ++out.non_manifold;
    } else if (h[s].from == h[s + 1].from) {
      ++out.flipped;
    } else {
      const HalfEdge &p = h[s], &q = h[s + 1];
      out.quads.push_back({p.from, p.to, p.opposite, q.opposite});
      out.faces.push_back({p.face, q.face});
    }
    s = e;
  }
  return out;
}

}  // namespace facesr
