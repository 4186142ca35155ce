#pragma once
// SIREN MLP (Sitzmann et al. 2020): sine layers sin(ω0 (W x + b)) and a
// linear output layer, with the paper's initialisation so activations stay
// well distributed at any depth. Layers are registered as "0", "1", ... so
// parameters are named "<module>.<layer>.weight|bias".
#include <vector>

#include <torch/torch.h>

namespace facesr {

class SirenImpl : public torch::nn::Module {
 public:
  SirenImpl(int64_t in, const std::vector<int>& hidden, int64_t out, double omega0);

  torch::Tensor forward(const torch::Tensor& x) { return from_first(first_linear(x)); }
  // The first layer's affine map W0 x + b0 alone. It commutes with any
  // weighted average whose weights sum to one, which is what lets the
  // upsampling interpolate this (narrow) result instead of the (wide) input.
  torch::Tensor first_linear(const torch::Tensor& x) { return layers_[0]->forward(x); }
  // Everything after the first affine map.
  torch::Tensor from_first(const torch::Tensor& pre);

 private:
  std::vector<torch::nn::Linear> layers_;
  double omega0_;
};
TORCH_MODULE(Siren);

}  // namespace facesr
