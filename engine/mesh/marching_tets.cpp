#include "mesh/marching_tets.h"

#include <unordered_map>

#include <Eigen/Geometry>

namespace facesr {

TriMesh marching_tets(const Grid& g, const std::vector<float>& field) {
  // Exact zeros would put a surface vertex on a grid node from several edges
  // (coincident vertices, zero-area triangles); nudge them to the outside.
  std::vector<float> f(field);
  for (float& v : f)
    if (v == 0.0f) v = 1e-7f;
  std::unordered_map<uint64_t, int> edge_vertex;
  std::vector<Vec3> verts;
  std::vector<Vec3i> tris;
  auto vertex_on_edge = [&](long a, long b, const Vec3& pa, const Vec3& pb) {
    const uint64_t key = a < b ? (uint64_t(a) << 32 | uint64_t(b)) : (uint64_t(b) << 32 | uint64_t(a));
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    const double fa = f[a], fb = f[b];
    const double t = fa / (fa - fb);
    verts.push_back(pa + t * (pb - pa));
    edge_vertex.emplace(key, int(verts.size() - 1));
    return int(verts.size() - 1);
  };
  static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                 {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  for (int k = 0; k + 1 < g.nz; ++k)
    for (int j = 0; j + 1 < g.ny; ++j)
      for (int i = 0; i + 1 < g.nx; ++i) {
        long id[8];
        bool any_in = false, any_out = false;
        for (int c = 0; c < 8; ++c) {
          id[c] = g.index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          (f[id[c]] < 0 ? any_in : any_out) = true;
        }
        if (!any_in || !any_out) continue;
        for (const auto& tet : kuhn) {
          long n[4];
          Vec3 p[4];
          std::vector<int> in, out;
          for (int a = 0; a < 4; ++a) {
            const int c = tet[a];
            n[a] = id[c];
            p[a] = g.node(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
            (f[n[a]] < 0 ? in : out).push_back(a);
          }
          if (in.empty() || out.empty()) continue;
          auto ev = [&](int a, int b) { return vertex_on_edge(n[a], n[b], p[a], p[b]); };
          Vec3 cin = Vec3::Zero(), cout = Vec3::Zero();
          for (int a : in) cin += p[a];
          for (int a : out) cout += p[a];
          const Vec3 outward = cout / double(out.size()) - cin / double(in.size());
          auto emit = [&](int v0, int v1, int v2) {
            if (v0 == v1 || v1 == v2 || v0 == v2) return;
            const Vec3 nrm = (verts[v1] - verts[v0]).cross(verts[v2] - verts[v0]);
            if (nrm.dot(outward) < 0) std::swap(v1, v2);
            tris.emplace_back(v0, v1, v2);
          };
          if (in.size() == 1 || out.size() == 1) {
            const int lone = in.size() == 1 ? in[0] : out[0];
            const auto& others = in.size() == 1 ? out : in;
            emit(ev(lone, others[0]), ev(lone, others[1]), ev(lone, others[2]));
          } else {
            const int a0 = in[0], a1 = in[1], b0 = out[0], b1 = out[1];
            const int q0 = ev(a0, b0), q1 = ev(a0, b1), q2 = ev(a1, b1), q3 = ev(a1, b0);
            emit(q0, q1, q2);
            emit(q0, q2, q3);
          }
        }
      }
  TriMesh m;
  m.V.resize(long(verts.size()), 3);
  for (size_t v = 0; v < verts.size(); ++v) m.V.row(long(v)) = verts[v].transpose();
  m.F.resize(long(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) m.F.row(long(t)) = tris[t].transpose().cast<int32_t>();
  return m;
}

}  // namespace facesr
