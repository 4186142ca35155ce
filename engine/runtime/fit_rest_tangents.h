#pragma once
// Measures a model's rest tangents (sr/rest_tangents.h) on a dataset's
// training frames: for every blendshape that some training frame has alone
// at a small weight, the smallest such frame gives its LR direction and the
// model's residual there. Frames held out for validation are never used.
#include <string>

#include <nlohmann/json.hpp>

#include "sr/sr_model.h"

namespace facesr {

struct RestTangentFitOptions {
  int validation_every = 10;  // as `facesr train`: these frames are not used
  double max_weight = 0.1;    // frames with the shape above this are not "near rest"
  double fade = 0.05, ridge = 1e-3;
};

struct RestTangentFit {
  RestTangents tangents;
  // Per shape: sequence, frame, weight, and the frame's mean per-vertex
  // error (cm) of the model without and with the correction.
  nlohmann::json shapes = nlohmann::json::array();
  std::vector<std::string> unmeasured;  // dataset shapes never alone at a small weight
};

// `model` must be of kind "sr" and match the dataset's rig; its own rest
// tangents, if any, are ignored (the fit is of the network alone). Error
// when no training frame has a single shape at a weight in (0, max_weight].
RestTangentFit fit_rest_tangents(const SrModel& model, const std::string& dataset_dir,
                                 const RestTangentFitOptions& opt);

}  // namespace facesr
