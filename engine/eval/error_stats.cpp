#include "eval/error_stats.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace facesr {

ErrorStats error_stats(std::vector<double> values) {
  require(!values.empty(), "error statistics: no values given");
  ErrorStats s;
  s.count = long(values.size());
  double sum = 0;
  s.min = s.max = values[0];
  for (size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (!std::isfinite(v)) throw Error("error statistics: value " + std::to_string(i) + " is not finite");
    sum += v;
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
  }
  s.mean = sum / double(values.size());
  // Second pass around the mean: sum of squares minus squared sum cancels badly
  // when the spread is tiny against the mean (a biased method).
  double ss = 0;
  for (const double v : values) ss += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(ss / double(values.size()));
  const size_t n = values.size(), mid = n / 2;
  std::nth_element(values.begin(), values.begin() + long(mid), values.end());
  s.median = values[mid];
  if (n % 2 == 0) s.median = 0.5 * (s.median + *std::max_element(values.begin(), values.begin() + long(mid)));
  return s;
}

ErrorStats scaled(const ErrorStats& s, double scale) {
  require(std::isfinite(scale) && scale > 0, "error statistics: scale must be finite and > 0");
  ErrorStats r = s;
  r.mean /= scale;
  r.median /= scale;
  r.std /= scale;
  r.max /= scale;
  r.min /= scale;
  return r;
}

}  // namespace facesr
