#pragma once
// `facesr eval`: the trained network ("ours") against the paper's baselines
// (embedded, RBF, MLS, β-VAE) on a dataset's test split (or on the training
// split's held-out validation frames, for choosing a model without looking at
// the test split), through
// engine/eval's metrics. Lives beside the trainer because "ours" and "vae"
// run in LibTorch here.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rig/rig.h"

namespace facesr {

struct ModelEvaluationOptions {
  std::string dataset_dir;
  std::string model_path;  // "ours" (optional if not among the methods)
  std::string vae_path;    // "vae" (optional)
  // Those available are run. "blendshape": the linear blendshape surface at
  // each frame's ARKit weights (baselines/blendshape.h).
  std::vector<std::string> methods{"ours", "embedded", "blendshape", "rbf", "mls", "vae"};
  std::string out_dir;     // CSV, SVG, pictures, report.json
  // "test": the manifest's test split. "validation": every
  // validation_every-th frame of the training split, the frames `facesr
  // train --validation-every` (same n) holds out; RBF and MLS then fit on the
  // remaining training frames.
  std::string split = "test";
  int validation_every = 10;
  int pictures = 4;        // test frames pictured (evenly spaced)
  // Lip contact on every method's surface and on the HR reference
  // (eval/lip_penetration.h): report.json "penetration".
  bool penetration = true;
  int spectral_k = 100;    // 0: no low/high band split (faster)
  // σ (cm) and μ for the baselines; <= 0: fitted on up to fit_frames training
  // frames over a grid scaled by the LR cell size.
  double rbf_sigma_cm = 0, rbf_regularization = -1, mls_sigma_cm = 0;
  int fit_frames = 24;
  bool progress = true;
};

// Returns the evaluation report's JSON (engine/eval) plus "baselines" (the σ
// and μ used and how they were chosen) and "timing" (ms per frame of each
// method). Throws Error (before writing) on a model for another rig, a
// method that cannot run (e.g. "vae" without a file when asked for
// explicitly), or a bad dataset.
nlohmann::json evaluate_models(const Rig& rig, const ModelEvaluationOptions& opt, std::string* markdown = nullptr);

}  // namespace facesr
