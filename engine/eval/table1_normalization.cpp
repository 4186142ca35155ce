#include "eval/table1_normalization.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace facesr {

double table1_normalizer(const std::vector<std::vector<double>>& frame_means) {
  require(!frame_means.empty(), "table 1 normalisation: no methods given");
  double mx = 0;
  for (size_t m = 0; m < frame_means.size(); ++m) {
    require(!frame_means[m].empty(), "table 1 normalisation: method " + std::to_string(m) + " has no frames");
    for (size_t f = 0; f < frame_means[m].size(); ++f) {
      const double v = frame_means[m][f];
      if (!(std::isfinite(v) && v >= 0))
        throw Error("table 1 normalisation: method " + std::to_string(m) + ", frame " + std::to_string(f) +
                    ": frame mean error is not a finite value >= 0");
      mx = std::max(mx, v);
    }
  }
  return mx;
}

std::vector<ErrorStats> table1_normalized_stats(const std::vector<std::vector<double>>& frame_means) {
  const double norm = table1_normalizer(frame_means);
  std::vector<ErrorStats> out;
  out.reserve(frame_means.size());
  for (const auto& fm : frame_means) {
    const ErrorStats s = error_stats(fm);
    out.push_back(norm > 0 ? scaled(s, norm) : s);
  }
  return out;
}

}  // namespace facesr
