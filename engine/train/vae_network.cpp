#include "train/vae_network.h"

#include "core/error.h"

namespace facesr {

namespace F = torch::nn::functional;

VaeNetworkImpl::VaeNetworkImpl(const SrArchitecture& arch, int64_t num_lr, int64_t num_hr)
    : arch_(arch), N_(num_lr), M_(num_hr) {
  require(arch.kind == "vae", "VaeNetwork: architecture kind is '" + arch.kind + "', expected 'vae'");
  auto enc = register_module("encoder", torch::nn::ModuleList());
  int64_t in = 3 * N_;
  for (int w : arch.vae_encoder) {
    enc_.push_back(torch::nn::Linear(in, w));
    enc->push_back(enc_.back());
    in = w;
  }
  mu_ = register_module("mu", torch::nn::Linear(in, arch.vae_latent));
  logvar_ = register_module("logvar", torch::nn::Linear(in, arch.vae_latent));
  auto dec = register_module("decoder", torch::nn::ModuleList());
  in = arch.vae_latent;
  for (int w : arch.vae_decoder) {
    dec_.push_back(torch::nn::Linear(in, w));
    dec->push_back(dec_.back());
    in = w;
  }
  out_ = register_module("out", torch::nn::Linear(in, 3 * M_));
}

VaeNetworkImpl::Output VaeNetworkImpl::forward(const torch::Tensor& lr_disp, bool sample) {
  require(lr_disp.dim() == 3 && lr_disp.size(1) == N_ && lr_disp.size(2) == 3,
          "VaeNetwork: input must be B × " + std::to_string(N_) + " × 3");
  const int64_t B = lr_disp.size(0);
  const auto act = F::LeakyReLUFuncOptions().negative_slope(arch_.leaky_slope);
  torch::Tensor h = lr_disp.reshape({B, 3 * N_}) / arch_.input_scale;
  for (auto& l : enc_) h = F::leaky_relu(l->forward(h), act);
  Output o;
  o.mu = mu_->forward(h);
  o.logvar = logvar_->forward(h);
  torch::Tensor z = o.mu;
  if (sample) z = o.mu + torch::exp(0.5 * o.logvar) * torch::randn_like(o.mu);
  for (auto& l : dec_) z = F::leaky_relu(l->forward(z), act);
  o.hr_disp = out_->forward(z).view({B, M_, 3}) * arch_.output_scale;
  return o;
}

torch::Tensor vae_loss(const VaeNetworkImpl::Output& o, const torch::Tensor& target, double output_scale,
                       double beta) {
  const int64_t B = target.size(0);
  const auto recon = ((o.hr_disp - target) / output_scale).pow(2).sum() / double(B);
  const auto kl = -0.5 * (1 + o.logvar - o.mu.pow(2) - o.logvar.exp()).sum() / double(B);
  return recon + beta * kl;
}

}  // namespace facesr
