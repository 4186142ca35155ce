#pragma once
// The β-VAE baseline (paper appendix A.4; Higgins et al. 2016): fully
// connected encoder (1024, 512) from the flattened LR displacements to a
// 128-dim Gaussian latent, decoder (256, 1024, 4096) to the flattened HR
// displacements, Leaky ReLU hidden activations. Parameter names follow
// parameter_shapes() for kind "vae".
#include <vector>

#include <torch/torch.h>

#include "sr/sr_architecture.h"

namespace facesr {

class VaeNetworkImpl : public torch::nn::Module {
 public:
  VaeNetworkImpl(const SrArchitecture& arch, int64_t num_lr, int64_t num_hr);

  struct Output {
    torch::Tensor hr_disp;     // B × M × 3, cm
    torch::Tensor mu, logvar;  // B × latent
  };
  // sample: draw the latent by reparameterisation (training); otherwise use
  // the mean (evaluation, deterministic).
  Output forward(const torch::Tensor& lr_disp, bool sample);

  const SrArchitecture& arch() const { return arch_; }

 private:
  SrArchitecture arch_;
  int64_t N_, M_;
  std::vector<torch::nn::Linear> enc_, dec_;
  torch::nn::Linear mu_{nullptr}, logvar_{nullptr}, out_{nullptr};
};
TORCH_MODULE(VaeNetwork);

// Per frame Σ (Δx̂ − Δx)² in units of output_scale, plus β · KL(q(z|x) ‖ N(0, I)),
// averaged over the batch.
torch::Tensor vae_loss(const VaeNetworkImpl::Output& out, const torch::Tensor& target, double output_scale,
                       double beta);

}  // namespace facesr
