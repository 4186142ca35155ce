#pragma once
#include <string>

#include <torch/torch.h>

namespace facesr {

// "cpu", "cuda" or "auto" (CUDA when this LibTorch build has it and a GPU is
// present, else the CPU). Asking for "cuda" where there is none is an Error.
torch::Device training_device(const std::string& choice);

// Uses every core for intra-op parallelism (LibTorch may start with one).
void use_all_cores();

}  // namespace facesr
