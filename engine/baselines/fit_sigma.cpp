#include "baselines/fit_sigma.h"

#include <cmath>
#include <string>

#include "baselines/mls.h"
#include "baselines/rbf.h"
#include "core/error.h"

namespace facesr {

namespace {

template <class Baseline>
double fit_sigma(const char* name, const SrGeometry& g, const std::vector<const float*>& lr_frames,
                 const std::vector<const float*>& hr_frames, const std::vector<double>& candidates_cm,
                 std::vector<double>* errors) {
  require(!candidates_cm.empty(), std::string(name) + " sigma fit: no candidates");
  std::vector<double> err;
  double best = candidates_cm.front(), best_err = 0;
  for (size_t c = 0; c < candidates_cm.size(); ++c) {
    const Baseline b(g, candidates_cm[c]);
    const double e = mean_vertex_error(g.num_hr, lr_frames, hr_frames,
                                       [&](const float* lr, float* hr) { b.apply(lr, hr); });
    err.push_back(e);
    if (c == 0 || e < best_err) {
      best = candidates_cm[c];
      best_err = e;
    }
  }
  if (errors) *errors = std::move(err);
  return best;
}

}  // namespace

double mean_vertex_error(int num_hr, const std::vector<const float*>& lr_frames,
                         const std::vector<const float*>& hr_frames,
                         const std::function<void(const float*, float*)>& apply) {
  require(!lr_frames.empty(), "sigma fit: no frames");
  require(lr_frames.size() == hr_frames.size(), "sigma fit: " + std::to_string(lr_frames.size()) +
                                                    " LR frames but " + std::to_string(hr_frames.size()) +
                                                    " HR frames");
  std::vector<float> pred(size_t(num_hr) * 3);
  double sum = 0;
  for (size_t f = 0; f < lr_frames.size(); ++f) {
    require(lr_frames[f] && hr_frames[f], "sigma fit: frame " + std::to_string(f) + " is null");
    apply(lr_frames[f], pred.data());
    for (int j = 0; j < num_hr; ++j) {
      double e2 = 0;
      for (int c = 0; c < 3; ++c) {
        const double d = double(pred[size_t(j) * 3 + size_t(c)]) - double(hr_frames[f][size_t(j) * 3 + size_t(c)]);
        e2 += d * d;
      }
      sum += std::sqrt(e2);
    }
  }
  return sum / (double(lr_frames.size()) * double(num_hr));
}

double fit_rbf_sigma(const SrGeometry& g, const std::vector<const float*>& lr_frames,
                     const std::vector<const float*>& hr_frames, const std::vector<double>& candidates_cm,
                     std::vector<double>* errors) {
  return fit_sigma<RbfBaseline>("RBF", g, lr_frames, hr_frames, candidates_cm, errors);
}

RbfParams fit_rbf_params(const SrGeometry& g, const std::vector<const float*>& lr_frames,
                         const std::vector<const float*>& hr_frames, const std::vector<double>& sigma_candidates_cm,
                         const std::vector<double>& regularization_candidates, std::vector<double>* errors) {
  require(!sigma_candidates_cm.empty() && !regularization_candidates.empty(), "RBF parameter fit: no candidates");
  std::vector<double> err;
  RbfParams best;
  double best_err = 0;
  for (double mu : regularization_candidates)
    for (double sigma : sigma_candidates_cm) {
      const RbfBaseline b(g, sigma, mu);
      const double e = mean_vertex_error(g.num_hr, lr_frames, hr_frames,
                                         [&](const float* lr, float* hr) { b.apply(lr, hr); });
      if (err.empty() || e < best_err) {
        best = {sigma, mu};
        best_err = e;
      }
      err.push_back(e);
    }
  if (errors) *errors = std::move(err);
  return best;
}

double fit_mls_sigma(const SrGeometry& g, const std::vector<const float*>& lr_frames,
                     const std::vector<const float*>& hr_frames, const std::vector<double>& candidates_cm,
                     std::vector<double>* errors) {
  return fit_sigma<MlsBaseline>("MLS", g, lr_frames, hr_frames, candidates_cm, errors);
}

}  // namespace facesr
