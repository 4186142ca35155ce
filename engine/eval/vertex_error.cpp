#include "eval/vertex_error.h"

#include <cmath>

#include "core/error.h"

namespace facesr {

std::vector<double> vertex_error(const std::vector<float>& predicted_disp, const std::vector<float>& reference_disp,
                                 const std::string& who) {
  require(predicted_disp.size() == reference_disp.size(),
          who + ": the prediction has " + std::to_string(predicted_disp.size()) + " floats and the reference " +
              std::to_string(reference_disp.size()));
  require(predicted_disp.size() % 3 == 0 && !predicted_disp.empty(),
          who + ": " + std::to_string(predicted_disp.size()) + " floats are not a non-empty M x 3 array");
  const size_t M = predicted_disp.size() / 3;
  std::vector<double> d(M);
  for (size_t v = 0; v < M; ++v) {
    double s = 0;
    for (size_t k = 3 * v; k < 3 * v + 3; ++k) {
      // In double: nearby float displacements lose digits when subtracted in float.
      const double e = double(predicted_disp[k]) - double(reference_disp[k]);
      s += e * e;
    }
    d[v] = std::sqrt(s);
    // Not require(): it would build the message for every vertex of every frame.
    if (!std::isfinite(d[v])) throw Error(who + ": vertex " + std::to_string(v) + " has a non-finite displacement");
  }
  return d;
}

double frame_mean_error(const std::vector<float>& predicted_disp, const std::vector<float>& reference_disp,
                        const std::string& who) {
  const std::vector<double> d = vertex_error(predicted_disp, reference_disp, who);
  double sum = 0;
  for (const double x : d) sum += x;
  return sum / double(d.size());
}

}  // namespace facesr
