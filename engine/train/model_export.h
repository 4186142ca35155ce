#pragma once
// Between LibTorch modules and the engine's model file (sr/sr_model.h).
#include <torch/torch.h>

#include "sr/sr_model.h"

namespace facesr {

// Copies the module's parameters into model.tensors in parameter_shapes()
// order. Error if a parameter is missing or has another shape (the module
// and the architecture disagree).
void export_parameters(torch::nn::Module& module, SrModel& model);

// Loads model.tensors into the module's parameters (same checks).
void import_parameters(const SrModel& model, torch::nn::Module& module);

}  // namespace facesr
