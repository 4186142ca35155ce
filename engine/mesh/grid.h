#pragma once
#include <vector>

#include "core/types.h"

namespace facesr {

// Regular grid of nodes: x = origin + h * (i, j, k).
struct Grid {
  Vec3 origin = Vec3::Zero();
  double h = 1;
  int nx = 0, ny = 0, nz = 0;
  long size() const { return long(nx) * ny * nz; }
  long index(int i, int j, int k) const { return (long(k) * ny + j) * nx + i; }
  Vec3 node(int i, int j, int k) const { return origin + h * Vec3(i, j, k); }
  // Grid covering [lo, hi] with `pad` extra nodes on each side.
  static Grid covering(const Vec3& lo, const Vec3& hi, double h, int pad);
};

class SurfaceQuery;

// Signed distance (negative inside) of a closed surface at every grid node.
// |d| is exact up to `band` and clamped to band beyond it. The sign comes
// from ray parity along grid lines in x, y and z with a majority vote, so one
// ray grazing an edge cannot flip a whole row.
std::vector<float> signed_distance_grid(const SurfaceQuery& surface, const Grid& grid, double band);

}  // namespace facesr
