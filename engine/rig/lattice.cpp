#include "rig/lattice.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "mesh/tet_mesh.h"

namespace facesr {
namespace {
// Corner bit masks (x = 1, y = 2, z = 4) of the six Kuhn tets: monotone paths
// from corner 0 to corner 7, conforming across neighbouring cubes.
const int kKuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
}  // namespace

void lattice_locate(const Lattice& L, const Vec3& p, long& cell, int& kuhn) {
  const Vec3 q = (p - L.origin) / L.cell;
  int ijk[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    ijk[a] = std::clamp(int(std::floor(q[a])), 0, L.dims[a] - 1);
    f[a] = q[a] - ijk[a];
  }
  cell = (long(ijk[2]) * L.dims[1] + ijk[1]) * L.dims[0] + ijk[0];
  const double u = f[0], v = f[1], w = f[2];
  if (u >= v && v >= w) kuhn = 0;
  else if (u >= w && w >= v) kuhn = 1;
  else if (v >= u && u >= w) kuhn = 2;
  else if (v >= w && w >= u) kuhn = 3;
  else if (w >= u && u >= v) kuhn = 4;
  else kuhn = 5;
}

TetMesh lattice_mesh(const Lattice& L, const std::vector<long>& cells, std::vector<long>& first_tet) {
  TetMesh m;
  std::unordered_map<long, int> node_id;
  std::vector<Vec3> nodes;
  const long nx = L.dims[0] + 1, ny = L.dims[1] + 1;
  auto node = [&](int i, int j, int k) {
    const long key = (long(k) * ny + j) * nx + i;
    auto it = node_id.find(key);
    if (it != node_id.end()) return it->second;
    nodes.push_back(L.origin + L.cell * Vec3(i, j, k));
    node_id.emplace(key, int(nodes.size() - 1));
    return int(nodes.size() - 1);
  };
  first_tet.assign(size_t(L.dims[0]) * L.dims[1] * L.dims[2], -1);
  std::vector<Vec4i> tets;
  for (long c : cells) {
    const int i = int(c % L.dims[0]), j = int((c / L.dims[0]) % L.dims[1]), k = int(c / (long(L.dims[0]) * L.dims[1]));
    int corner[8];
    for (int b = 0; b < 8; ++b) corner[b] = node(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
    first_tet[c] = long(tets.size());
    for (const auto& kt : kKuhn) tets.emplace_back(corner[kt[0]], corner[kt[1]], corner[kt[2]], corner[kt[3]]);
  }
  m.X.resize(long(nodes.size()), 3);
  for (size_t n = 0; n < nodes.size(); ++n) m.X.row(long(n)) = nodes[n].transpose();
  m.T.resize(long(tets.size()), 4);
  for (size_t t = 0; t < tets.size(); ++t) {
    Vec4i q = tets[t];
    if (tet_signed_volume(m.X.row(q[0]), m.X.row(q[1]), m.X.row(q[2]), m.X.row(q[3])) < 0) std::swap(q[1], q[2]);
    m.T.row(long(t)) = q.cast<int32_t>().transpose();
  }
  return m;
}

}  // namespace facesr
