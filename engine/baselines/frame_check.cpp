#include "baselines/frame_check.h"

#include <cmath>

#include "core/error.h"

namespace facesr {

void require_finite_frame(const float* v, int n, const std::string& what) {
  require(v != nullptr, what + ": null displacement array");
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      require(std::isfinite(v[size_t(i) * 3 + size_t(c)]),
              what + ": displacement of node " + std::to_string(i) + " is not finite");
}

void require_frame_size(const std::vector<float>& v, int n, const std::string& what) {
  require(v.size() == size_t(n) * 3, what + ": displacement array has " + std::to_string(v.size()) +
                                         " values, expected " + std::to_string(size_t(n) * 3) + " (" +
                                         std::to_string(n) + " nodes × 3)");
}

}  // namespace facesr
