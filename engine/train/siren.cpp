#include "train/siren.h"

#include <cmath>

namespace facesr {

SirenImpl::SirenImpl(int64_t in, const std::vector<int>& hidden, int64_t out, double omega0) : omega0_(omega0) {
  std::vector<int64_t> widths{in};
  for (int h : hidden) widths.push_back(h);
  widths.push_back(out);
  torch::NoGradGuard no_grad;
  for (size_t l = 0; l + 1 < widths.size(); ++l) {
    auto lin = register_module(std::to_string(l), torch::nn::Linear(widths[l], widths[l + 1]));
    // First layer U(-1/n, 1/n) so sin(ω0 ·) spans several periods over
    // inputs in [-1, 1]; later layers U(-√(6/n)/ω0, √(6/n)/ω0) so each sine
    // layer's input stays unit-variance (Sitzmann et al. 2020, §3.2).
    const double n = double(widths[l]);
    const double bound = l == 0 ? 1.0 / n : std::sqrt(6.0 / n) / omega0;
    lin->weight.uniform_(-bound, bound);
    lin->bias.uniform_(-1.0 / std::sqrt(n), 1.0 / std::sqrt(n));
    layers_.push_back(lin);
  }
}

torch::Tensor SirenImpl::from_first(const torch::Tensor& pre) {
  torch::Tensor h = pre;
  for (size_t l = 1; l < layers_.size(); ++l) h = layers_[l]->forward(torch::sin(omega0_ * h));
  return h;
}

}  // namespace facesr
