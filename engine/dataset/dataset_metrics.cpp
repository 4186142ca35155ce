#include "dataset/dataset_metrics.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace facesr {
namespace {

size_t checked_vertex_count(const DatasetFrame& f) {
  require(f.hr_disp.size() == f.embedded_disp.size() && f.hr_disp.size() % 3 == 0,
          "embedded error: hr_disp has " + std::to_string(f.hr_disp.size()) + " floats and embedded_disp " +
              std::to_string(f.embedded_disp.size()) + " (both must be S x 3)");
  return f.hr_disp.size() / 3;
}

// In double: float differences of nearby displacements lose digits otherwise.
double distance(const DatasetFrame& f, size_t v) {
  double s = 0;
  for (size_t k = 3 * v; k < 3 * v + 3; ++k) {
    const double e = double(f.hr_disp[k]) - double(f.embedded_disp[k]);
    s += e * e;
  }
  return std::sqrt(s);
}

}  // namespace

std::vector<float> embedded_error_per_vertex(const DatasetFrame& f) {
  const size_t S = checked_vertex_count(f);
  std::vector<float> d(S);
  for (size_t v = 0; v < S; ++v) d[v] = float(distance(f, v));
  return d;
}

void embedded_error(const DatasetFrame& f, double& mean_cm, double& max_cm) {
  const size_t S = checked_vertex_count(f);
  double sum = 0, mx = 0;
  for (size_t v = 0; v < S; ++v) {
    const double d = distance(f, v);
    sum += d;
    mx = std::max(mx, d);
  }
  mean_cm = S ? sum / double(S) : 0;
  max_cm = mx;
}

}  // namespace facesr
