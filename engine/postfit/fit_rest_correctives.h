#pragma once
// Measures a model's near-rest correctives (sr/rest_correctives.h) on a
// dataset's training frames: for every blendshape that some training frame
// has alone at a small weight, each such frame (one per distinct weight)
// gives a sample of the model's residual, the smallest also the shape's LR
// direction. Frames held out for validation are never used.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sr/sr_model.h"

namespace facesr {

struct RestCorrectiveFitOptions {
  int validation_every = 10;  // as `facesr train`: these frames are not used
  // Samples are frames with the shape alone at a weight in (0, max_weight]
  // and at most fade / 2 (where φ ≥ 0.94, so dividing by it is safe).
  double max_weight = 0.1;
  double fade = 0.2, ridge = 1e-3;
};

struct RestCorrectiveFit {
  RestCorrectives correctives;
  // Per shape: {shape, samples: [{sequence, frame, weight, network_error_cm,
  // corrected_error_cm}]}: the frame's mean per-vertex error (cm) of the
  // model without and with the correction.
  nlohmann::json shapes = nlohmann::json::array();
  std::vector<std::string> unmeasured;  // dataset shapes never alone at a small weight
};

// `model` must be of kind "sr" and match the dataset's rig; its own
// correctives, if any, are ignored (the fit is of the network alone). Error
// when no training frame has a single shape at a usable weight.
RestCorrectiveFit fit_rest_correctives(const SrModel& model, const std::string& dataset_dir,
                                       const RestCorrectiveFitOptions& opt);

}  // namespace facesr
