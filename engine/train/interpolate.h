#pragma once
#include <torch/torch.h>

namespace facesr {

// The coordinate-based upsampling's weighted sum (paper eq. 1):
// out[b, j, :] = Σ_q w[j, q] · f[b, idx[j, q], :], for w: M × K weights,
// idx: M × K long node indices, f: B × N × C features → B × M × C.
// Differentiable in both w and f. A custom autograd function because
// LibTorch 1.13's sparse product gives no gradient for the sparse values,
// and the plain gather-and-sum materialises B × M × K × C.
torch::Tensor interpolate_neighbours(const torch::Tensor& w, const torch::Tensor& idx, const torch::Tensor& f);

}  // namespace facesr
