#include "sim/block_model.h"

#include "core/error.h"
#include "rig/lattice.h"

namespace facesr {

SimModel make_block_model(int nx, int ny, int nz, double cell, const MaterialParams& material) {
  require(nx > 0 && ny > 0 && nz > 0 && cell > 0, "block model: sizes must be positive");
  Rig r;
  r.name = "block";
  Lattice L;
  L.cell = cell;
  L.dims = {nx, ny, nz};
  std::vector<long> cells, first;
  for (long c = 0; c < long(nx) * ny * nz; ++c) cells.push_back(c);
  r.lr.mesh = lattice_mesh(L, cells, first);
  const long nt = r.lr.mesh.T.rows();
  const double height = nz * cell;
  for (long t = 0; t < nt; ++t) {
    double z = 0;
    for (int k = 0; k < 4; ++k) z += r.lr.mesh.X(r.lr.mesh.T(t, k), 2) / 4;
    const bool in_muscle = z > height / 3 && z < 2 * height / 3;
    r.lr.muscle.push_back(in_muscle ? 0 : -1);
    r.lr.muscle_fraction.push_back(in_muscle ? 1.0f : 0.0f);
    r.lr.fibre.insert(r.lr.fibre.end(), {0.0f, 1.0f, 0.0f});
  }
  std::vector<int> top;
  for (int v = 0; v < r.lr.mesh.X.rows(); ++v) {
    const double z = r.lr.mesh.X(v, 2);
    if (z < 1e-9 * cell) {
      r.lr.dirichlet.push_back(v);
      r.lr.dirichlet_bone.push_back(0);
    } else if (z > height - 1e-9 * cell) {
      top.push_back(v);
    }
  }
  // The top face is the "skin": one surface vertex per top node, tracked.
  r.surface.resize(long(top.size()), 3);
  for (size_t i = 0; i < top.size(); ++i) {
    r.surface.row(long(i)) = r.lr.mesh.X.row(top[i]);
    // Any tet holding the node embeds it exactly with a unit weight on it.
    for (long t = 0; t < nt; ++t) {
      int k = -1;
      for (int j = 0; j < 4; ++j)
        if (r.lr.mesh.T(t, j) == top[i]) k = j;
      if (k < 0) continue;
      r.lr.surface.tet.push_back(int32_t(t));
      for (int j = 0; j < 4; ++j) r.lr.surface.weights.push_back(j == k ? 1.0f : 0.0f);
      r.lr.surface.outside.push_back(0);
      break;
    }
    r.lr.tracks.push_back(int32_t(i));
    r.lr.track_area.push_back(float(cell * cell));
  }
  Muscle m;
  m.name = "block_muscle";
  r.muscles.push_back(m);
  r.blendshape_names = {"lift"};
  r.blendshape_deltas.assign(3 * top.size(), 0.0f);
  for (size_t i = 0; i < top.size(); ++i) r.blendshape_deltas[3 * i + 2] = float(0.5 * cell);
  r.activation = {1.0f};
  r.jaw.pivot = Vec3(0, 0, 0);
  return make_sim_model(r, Resolution::Low, material);
}

}  // namespace facesr
