#include <algorithm>
#include <cmath>

#include "mesh/grid.h"
#include "mesh/surface_query.h"

namespace facesr {

Grid Grid::covering(const Vec3& lo, const Vec3& hi, double h, int pad) {
  Grid g;
  g.h = h;
  g.origin = lo - Vec3::Constant(pad * h);
  const Vec3 ext = hi - lo;
  g.nx = int(std::ceil(ext.x() / h)) + 1 + 2 * pad;
  g.ny = int(std::ceil(ext.y() / h)) + 1 + 2 * pad;
  g.nz = int(std::ceil(ext.z() / h)) + 1 + 2 * pad;
  return g;
}

std::vector<float> signed_distance_grid(const SurfaceQuery& surface, const Grid& g, double band) {
  const long n = g.size();
  std::vector<uint8_t> votes(n, 0);
  const int dims[3] = {g.nx, g.ny, g.nz};
  // Irrational offsets keep scanlines off mesh vertices and edges.
  const double jitter[2] = {1.234567e-4 * g.h, 2.718281e-4 * g.h};
  for (int axis = 0; axis < 3; ++axis) {
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    const int n1 = dims[a1], n2 = dims[a2], n0 = dims[axis];
#pragma omp parallel for schedule(dynamic, 4)
    for (int r = 0; r < n1 * n2; ++r) {
      const int u = r % n1, v = r / n1;
      int ijk[3];
      ijk[axis] = 0;
      ijk[a1] = u;
      ijk[a2] = v;
      Vec3 o = g.node(ijk[0], ijk[1], ijk[2]);
      o[axis] -= g.h;
      o[a1] += jitter[0];
      o[a2] += jitter[1];
      Vec3 dir = Vec3::Zero();
      dir[axis] = 1;
      const auto hits = surface.all_hits(o, dir, (n0 + 1) * g.h);
      size_t h = 0;
      for (int i = 0; i < n0; ++i) {
        const double t = (i + 1) * g.h;
        while (h < hits.size() && hits[h] < t) ++h;
        if (h % 2 == 1) {
          ijk[axis] = i;
          votes[g.index(ijk[0], ijk[1], ijk[2])]++;
        }
      }
    }
  }
  std::vector<float> sd(n);
#pragma omp parallel for schedule(dynamic, 1024)
  for (long idx = 0; idx < n; ++idx) {
    const int i = int(idx % g.nx), j = int((idx / g.nx) % g.ny), k = int(idx / (long(g.nx) * g.ny));
    const auto c = surface.closest(g.node(i, j, k), band);
    const double d = c.tri >= 0 ? c.dist : band;
    sd[idx] = float(votes[idx] >= 2 ? -d : d);
  }
  return sd;
}

}  // namespace facesr
