#pragma once
// A model file's network run in LibTorch: the evaluation's "ours" and "vae"
// methods, and the reference the runtime's OpenCL inference is checked
// against.
#include <memory>

#include <torch/torch.h>

#include "sr/sr_model.h"

namespace facesr {

class TorchPredictor {
 public:
  explicit TorchPredictor(const SrModel& model);
  ~TorchPredictor();

  // lr: F × N × 3 LR displacements (cm) → F × M × 3 HR displacements (cm),
  // in batches of `batch` frames, without gradients.
  torch::Tensor predict(const torch::Tensor& lr, int batch = 6);
  torch::nn::Module& module();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
