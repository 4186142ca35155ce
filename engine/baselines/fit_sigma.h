#pragma once
// Choosing the baselines' Gaussian width σ (appendix A.2, A.3 leave it
// open) on training frames: the candidate whose reconstruction has the least
// mean per-vertex Euclidean error.
#include <functional>
#include <vector>

#include "sr/sr_geometry.h"

namespace facesr {

// lr_frames[f]: N × 3 displacements, hr_frames[f]: the matching M × 3 ground
// truth (cm). Returns the best candidate (the first of equals); `errors`
// (if given) receives each candidate's mean error in cm. Throws Error on no
// frames, mismatched frame counts, null frames or no candidates. The RBF
// σ fit uses the default regularisation.
double fit_rbf_sigma(const SrGeometry& g, const std::vector<const float*>& lr_frames,
                     const std::vector<const float*>& hr_frames, const std::vector<double>& candidates_cm,
                     std::vector<double>* errors = nullptr);
// RBF σ with its regularisation μ (RbfBaseline's third argument): the best
// pair of the grid; `errors` (if given) receives the mean errors with σ
// varying fastest (errors[m * sigmas + s]).
struct RbfParams {
  double sigma_cm = 0;
  double regularization = 0;
};
RbfParams fit_rbf_params(const SrGeometry& g, const std::vector<const float*>& lr_frames,
                         const std::vector<const float*>& hr_frames, const std::vector<double>& sigma_candidates_cm,
                         const std::vector<double>& regularization_candidates, std::vector<double>* errors = nullptr);
double fit_mls_sigma(const SrGeometry& g, const std::vector<const float*>& lr_frames,
                     const std::vector<const float*>& hr_frames, const std::vector<double>& candidates_cm,
                     std::vector<double>* errors = nullptr);

// Mean over frames and HR vertices of |predicted − truth| (cm) for any
// reconstruction `apply(lr, hr_out)`.
double mean_vertex_error(int num_hr, const std::vector<const float*>& lr_frames,
                         const std::vector<const float*>& hr_frames,
                         const std::function<void(const float*, float*)>& apply);

}  // namespace facesr
