#include "sim/assembled_stiffness.h"

#include "sim/material.h"

namespace facesr {

AssembledStiffness make_assembled_stiffness(const SimModel& m) {
  AssembledStiffness K;
  K.pattern = make_stiffness_pattern(m);
  return K;
}

void assemble_stiffness(const SimModel& m, const ElementHessian& H, AssembledStiffness& K) {
  const StiffnessPattern& p = K.pattern;
  K.tet_blocks.resize(90 * size_t(m.num_tets));
  K.blocks.resize(9 * p.num_blocks());
#pragma omp parallel for schedule(static)
  for (int t = 0; t < m.num_tets; ++t)
    fsr_tet_blocks(&H.C[81 * size_t(t)], &m.Dminv[9 * t], m.volume[t], &K.tet_blocks[90 * size_t(t)]);
  const int rows = int(p.row_offset.size()) - 1;
#pragma omp parallel for schedule(dynamic, 256)
  for (int v = 0; v < rows; ++v)
    for (int b = p.row_offset[v]; b < p.row_offset[v + 1]; ++b) {
      double A[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      for (int i = p.tet_offset[b]; i < p.tet_offset[b + 1]; ++i) {
        const int ref = p.tet_ref[i];
        const double* B = &K.tet_blocks[9 * size_t(ref >> 1)];
        if (ref & 1) {
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) A[3 * r + c] += B[3 * c + r];
        } else {
          for (int e = 0; e < 9; ++e) A[e] += B[e];
        }
      }
      for (int i = p.surf_offset[b]; i < p.surf_offset[b + 1]; ++i) {
        const int ref = p.surf_ref[i], vert = m.inc_all.vertices[ref >> 4];
        const double w = m.surf_weights[4 * vert + ((ref >> 2) & 3)] * m.surf_weights[4 * vert + (ref & 3)];
        const double* Hs = &H.surf[9 * size_t(vert)];
        for (int e = 0; e < 9; ++e) A[e] += w * Hs[e];
      }
      for (int e = 0; e < 9; ++e) K.blocks[9 * size_t(b) + e] = A[e];
    }
}

void stiffness_product(const AssembledStiffness& K, const std::vector<double>& dx, std::vector<double>& y) {
  const StiffnessPattern& p = K.pattern;
  const int rows = int(p.row_offset.size()) - 1;
  y.resize(3 * size_t(rows));
#pragma omp parallel for schedule(static)
  for (int v = 0; v < rows; ++v) {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int b = p.row_offset[v]; b < p.row_offset[v + 1]; ++b) {
      const double* A = &K.blocks[9 * size_t(b)];
      const double* x = &dx[3 * size_t(p.col[b])];
      s0 += A[0] * x[0] + A[1] * x[1] + A[2] * x[2];
      s1 += A[3] * x[0] + A[4] * x[1] + A[5] * x[2];
      s2 += A[6] * x[0] + A[7] * x[1] + A[8] * x[2];
    }
    y[3 * size_t(v)] = s0;
    y[3 * size_t(v) + 1] = s1;
    y[3 * size_t(v) + 2] = s2;
  }
}

}  // namespace facesr
