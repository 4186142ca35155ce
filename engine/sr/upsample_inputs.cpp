#include "sr/upsample_inputs.h"

#include <cmath>

namespace facesr {

std::vector<float> upsample_inputs(const SrArchitecture& arch, const SrGeometry& g) {
  const size_t M = size_t(g.num_hr), K = size_t(g.upsample_k);
  const std::vector<float>& xh_rest = g.hr_rest_lr_frame.empty() ? g.hr_rest : g.hr_rest_lr_frame;
  std::vector<float> u(M * K * 7);
  const double s = arch.coord_scale;
  for (size_t j = 0; j < M; ++j)
    for (size_t q = 0; q < K; ++q) {
      const size_t i = size_t(g.up_index[j * K + q]);
      float* row = &u[(j * K + q) * 7];
      double d2 = 0;
      for (int c = 0; c < 3; ++c) {
        const double xh = xh_rest[3 * j + c], xl = g.lr_rest[3 * i + c];
        row[c] = float((xh - arch.coord_center[c]) / s);
        row[3 + c] = float((xl - arch.coord_center[c]) / s);
        d2 += (xl - xh) * (xl - xh);
      }
      row[6] = float(std::sqrt(d2) / s);
    }
  return u;
}

}  // namespace facesr
