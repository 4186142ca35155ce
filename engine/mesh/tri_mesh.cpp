#include "mesh/tri_mesh.h"

#include <algorithm>
#include <map>
#include <unordered_map>

#include <Eigen/Geometry>

namespace facesr {

Points vertex_normals(const Points& V, const Tris& F) {
  Points N = Points::Zero(V.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);  // length = 2 * area: area weighting
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n.transpose();
  }
  for (int i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

std::vector<std::pair<int, int>> unique_edges(const Tris& F) {
  std::vector<std::pair<int, int>> e;
  e.reserve(F.rows() * 3);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      int a = F(f, k), b = F(f, (k + 1) % 3);
      e.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  return e;
}

std::vector<std::vector<int>> boundary_loops(const Tris& F) {
  // A directed edge without its reverse is on the boundary.
  std::map<std::pair<int, int>, int> count;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) count[{F(f, k), F(f, (k + 1) % 3)}]++;
  std::unordered_map<int, int> next;
  for (const auto& [e, c] : count)
    if (!count.count({e.second, e.first})) next[e.first] = e.second;
  std::vector<std::vector<int>> loops;
  while (!next.empty()) {
    const int start = next.begin()->first;
    std::vector<int> loop;
    int v = start;
    while (next.count(v)) {
      loop.push_back(v);
      const int w = next[v];
      next.erase(v);
      v = w;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<int> face_components(const Tris& F, long nv, int& count) {
  std::vector<int> parent(nv);
  for (long i = 0; i < nv; ++i) parent[i] = int(i);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 1; k < 3; ++k) parent[find(F(f, 0))] = find(F(f, k));
  std::unordered_map<int, int> id;
  std::vector<int> comp(F.rows());
  for (int f = 0; f < F.rows(); ++f) comp[f] = id.emplace(find(F(f, 0)), int(id.size())).first->second;
  count = int(id.size());
  return comp;
}

void bounding_box(const Points& V, Vec3& lo, Vec3& hi) {
  lo = V.colwise().minCoeff().transpose();
  hi = V.colwise().maxCoeff().transpose();
}

}  // namespace facesr
