#pragma once
// Models for runtime tests that need no training: the network with random
// (SIREN-initialised) weights on the coarse procedural rig, exported as a
// model file would hold it.
#include <memory>
#include <vector>

#include <torch/torch.h>

#include "sr/sr_model.h"

namespace facesr::fixtures {

std::shared_ptr<SrModel> random_model(bool feature_encoding = true, bool coordinate_upsampling = true,
                                      uint64_t seed = 1, bool embedded_skip = false,
                                      bool zero_rest = false, std::vector<int> recon_hidden = {64, 64});
// F frames of smooth LR displacements of a plausible size (a few mm): F × N × 3.
torch::Tensor lr_frames(const SrModel& m, int F);
// n normal random values (mean 0, standard deviation `scale`), from `seed`.
std::vector<float> random_values(size_t n, uint32_t seed, float scale);
// Largest |a_i − b_i|.
double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace facesr::fixtures
