#pragma once
// Summaries of per-frame timings shared by the benchmarks.
#include <algorithm>
#include <numeric>
#include <vector>

namespace facesr::bench_stats {

inline double mean(const std::vector<double>& v) {
  return v.empty() ? 0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

// The sample at rank ⌊0.95 n⌋ (at most the largest).
inline double p95(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(0.95 * double(v.size())))];
}

}  // namespace facesr::bench_stats
