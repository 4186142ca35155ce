#pragma once
// The paper's super-resolution network (§3, fig. 2) in LibTorch: positional
// encoding, EdgeConv feature encoding, coordinate-based upsampling with SIREN
// weights, SIREN surface reconstruction. Built from an SrArchitecture and the
// rig's SrGeometry; its named parameters are exactly parameter_shapes().
#include <vector>

#include <torch/torch.h>

#include "sr/coordinate_frame.h"
#include "sr/sr_architecture.h"
#include "sr/sr_geometry.h"
#include "train/edge_conv.h"
#include "train/siren.h"

namespace facesr {

class SrNetworkImpl : public torch::nn::Module {
 public:
  SrNetworkImpl(const SrArchitecture& arch, const SrGeometry& geometry);

  struct Output {
    torch::Tensor hr_disp;                // B × M × 3, cm
    std::vector<torch::Tensor> features;  // the S submodule outputs z̄_s, B × N × D_s (for L_reg)
  };
  // lr_disp: B × N × 3 LR node displacements from the LR rest pose, cm.
  Output forward(const torch::Tensor& lr_disp);

  // The LR-embedded surface displacement Σ_k w_jk Δx^L (B × M × 3, cm).
  torch::Tensor embedded(const torch::Tensor& lr_disp);
  // The encoded LR feature z^L (B × N × encoded_dim) alone.
  torch::Tensor encode(const torch::Tensor& lr_disp, std::vector<torch::Tensor>* features = nullptr);
  // Normalised interpolation weights w_ij, M × K, and the neighbour indices
  // they belong to (M × K long).
  torch::Tensor upsample_weights();
  const torch::Tensor& upsample_index() const { return up_index_; }

  const SrArchitecture& arch() const { return arch_; }

 private:
  // The network without the embedded skip and the rest subtraction.
  Output forward_network(const torch::Tensor& lr_disp);
  // Σ_k w_jk f_{idx_jk}: f is B × N × C, result B × M × C.
  torch::Tensor interpolate(const torch::Tensor& w, const torch::Tensor& f);

  SrArchitecture arch_;
  int64_t N_, M_, K_;
  // Index tensors are plain members, not buffers: Module::to(dtype) would
  // convert registered buffers to floating point. They follow the input's
  // device in encode().
  torch::Tensor pe_, graph_, up_index_, up_input_, embed_nodes_, embed_weights_;
  std::vector<EdgeConvBlock> blocks_;
  Siren weight_net_{nullptr}, recon_{nullptr};
  torch::Tensor free_weights_;
};
TORCH_MODULE(SrNetwork);


}  // namespace facesr
