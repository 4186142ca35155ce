#pragma once
// Hyperparameters of a super-resolution model (paper §3 and appendix table 3)
// and the names and shapes of its parameter tensors. The LibTorch module
// (engine/train) and the runtime's inference kernels are both built from this
// one description, so a model file says everything needed to run it.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace facesr {

struct SrArchitecture {
  // "sr": the paper's network. "vae": the β-VAE baseline (appendix A.4).
  std::string kind = "sr";

  // --- "sr" ---
  int pe_dim = 32;                      // positional encoding (D0 = 3 + pe_dim = 35)
  std::vector<int> encoder_dims{64, 128};  // D1..DS, one EdgeConv submodule each (S = 2)
  int graph_k = 5;                      // k of every EdgeConv k-NN graph
  int upsample_k = 20;                  // interpolation neighbours per HR vertex
  // Ablations (§5.4.1): without feature encoding the positional-encoded
  // input goes straight to the upsampling; without coordinate-based
  // upsampling the weights are free parameters over the upsample_k
  // Euclidean-nearest LR nodes.
  bool feature_encoding = true;
  bool coordinate_upsampling = true;
  // Not in the paper: add the LR-embedded displacement (the "embedded"
  // baseline) to the output, so the network learns the correction to it
  // (a residual connection). Off reproduces the paper.
  bool embedded_skip = false;
  // Not in the paper: subtract the network's output at the rest input, so
  // that zero LR displacement gives exactly zero HR displacement (both
  // simulators are at rest under zero controls). Without it a trained
  // network keeps a small constant offset at rest (measured on ICT: 0.0069 cm
  // per vertex), which loses to the embedded baseline on near-rest frames.
  bool zero_rest = false;
  std::vector<int> weight_hidden{64, 64};        // SIREN f_θ: 7 → ... → 1
  std::vector<int> recon_hidden{128, 128, 128};  // SIREN reconstruction: D → ... → 3
  double omega0 = 30;        // SIREN first-layer frequency (Sitzmann et al. 2020)
  double leaky_slope = 0.2;  // EdgeConv and shared FC activations (as DGCNN)

  // --- "vae" ---
  std::vector<int> vae_encoder{1024, 512};
  int vae_latent = 128;
  std::vector<int> vae_decoder{256, 1024, 4096};

  // --- both: data scaling, set by training from the training frames ---
  // The network sees lr_disp / input_scale and its raw output times
  // output_scale is the HR displacement (cm).
  double input_scale = 1, output_scale = 1;
  // SIREN coordinates are (x - coord_center) / coord_scale (rest poses, cm),
  // so they lie in about [-1, 1] whatever the head's size.
  std::array<double, 3> coord_center{0, 0, 0};
  double coord_scale = 1;

  // Width of the encoded LR feature: D0 + sum(encoder_dims), or D0 without FE.
  int encoded_dim() const;
  int input_dim() const { return 3 + pe_dim; }
};

nlohmann::json architecture_to_json(const SrArchitecture& a);
// Validates every field (kind, positive sizes, ranges); Errors name `source`
// and the key.
SrArchitecture architecture_from_json(const nlohmann::json& j, const std::string& source);

// Every parameter tensor of the model for N LR nodes and M HR vertices, in a
// fixed order, with its name (as LibTorch's named_parameters() spells it) and
// shape. A model file must hold exactly these.
std::vector<std::pair<std::string, std::vector<int64_t>>> parameter_shapes(const SrArchitecture& a, int N, int M);

}  // namespace facesr
