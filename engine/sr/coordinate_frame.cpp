#include "sr/coordinate_frame.h"

#include <algorithm>

namespace facesr {

void set_coordinate_frame(SrArchitecture& arch, const SrGeometry& g) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  auto grow = [&](const std::vector<float>& p) {
    for (size_t i = 0; i + 2 < p.size(); i += 3)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], double(p[i + c]));
        hi[c] = std::max(hi[c], double(p[i + c]));
      }
  };
  grow(g.lr_rest);
  grow(g.hr_rest);
  double half = 0;
  for (int c = 0; c < 3; ++c) {
    arch.coord_center[c] = 0.5 * (lo[c] + hi[c]);
    half = std::max(half, 0.5 * (hi[c] - lo[c]));
  }
  arch.coord_scale = half > 0 ? half : 1;
}

}  // namespace facesr
