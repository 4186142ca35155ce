#pragma once
// Not in the paper: a low-pass filter on what a model adds to the embedded
// surface. With the embedded skip the network's output is the embedded
// displacement e (the LR lattice's barycentric embedding of the surface)
// plus a learned correction r; the correction is predicted per vertex and
// carries small vertex-to-vertex noise that the embedded surface has not, so
// the network lost to the embedded baseline on the dihedral-angle metric
// (DAME) while winning on every distance. The filter keeps e and replaces r
// by K steps of uniform Laplacian (umbrella) smoothing over the surface's
// edges,
//   r ← r + λ (mean of r over the vertex's edge neighbours − r),  0 < λ ≤ 1,
// each step a convex combination, so it never amplifies any frequency and
// leaves a correction that is constant over the surface unchanged. It runs
// on the host after the network and before the near-rest correctives
// (sr/rest_correctives.h), which are fitted to the smoothed output.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sr/sr_geometry.h"

namespace facesr {

struct ResidualSmoothing {
  double lambda = 0.5;  // step size, (0, 1]
  int iterations = 0;   // K; 0: no smoothing
  bool empty() const { return iterations == 0; }
};

nlohmann::json residual_smoothing_to_json(const ResidualSmoothing& s);
// Errors name `source` and the key.
ResidualSmoothing residual_smoothing_from_json(const nlohmann::json& j, const std::string& source);
// 0 < λ ≤ 1, 0 ≤ K ≤ kMaxSmoothingIterations.
void validate_residual_smoothing(const ResidualSmoothing& s, const std::string& context);
constexpr int kMaxSmoothingIterations = 64;

// The load-time form: edge neighbours of every surface vertex and the
// embedding, from the model's geometry (hr_tris, embed_nodes, embed_weights).
class ResidualSmoother {
 public:
  ResidualSmoother(const ResidualSmoothing& s, const SrGeometry& g);
  // hr_disp (M × 3, cm) ← e + smoothed (hr_disp − e), e the embedding of
  // lr_disp (N × 3, cm). Uses scratch space: one call at a time.
  void apply(const float* lr_disp, float* hr_disp);

 private:
  ResidualSmoothing s_;
  int M_;
  std::vector<int32_t> start_, nbr_;  // CSR edge neighbours
  std::vector<int32_t> embed_nodes_;
  std::vector<float> embed_weights_, embedded_, r_, next_;
};

}  // namespace facesr
