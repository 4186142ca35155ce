#pragma once
// The paper's training loss (§3.4, eq. 4–7): L1 reconstruction of the HR
// displacements + α · face-normal loss + β · L2 norm of the intermediate
// encoder features. Each term is a sum as in the paper; the total is divided
// by the HR vertex count M and averaged over the batch, which only rescales
// it (Adam is insensitive to a constant loss scale) and makes it readable as
// about "cm of L1 per vertex".
#include <vector>

#include <torch/torch.h>

namespace facesr {

struct LossTerms {
  torch::Tensor total;   // scalar, what is minimised
  torch::Tensor recon;   // Σ_j ‖Δx̂_j − Δx_j‖₁ per frame (batch mean), cm
  torch::Tensor normal;  // Σ_k (1 − cos(n̂_k, n_k)) per frame (batch mean)
  torch::Tensor reg;     // Σ_s Σ_i ‖z̄_s,i‖₂ per frame (batch mean)
};

// pred, target: B × M × 3 displacements (cm); rest: M × 3 rest surface;
// tris: F × 3 long; features: the encoder's submodule outputs (may be empty).
// frame_weights (optional, B): multiplies each frame's L1 term (see
// relative_frame_weights); undefined means 1 for every frame, the paper's loss.
LossTerms sr_loss(const torch::Tensor& pred, const torch::Tensor& target, const torch::Tensor& rest,
                  const torch::Tensor& tris, const std::vector<torch::Tensor>& features, double alpha, double beta,
                  const torch::Tensor& frame_weights = {});

// Not in the paper. Per-frame weights w_f ∝ 1 / (e_f + floor_cm), where e_f
// is frame f's mean per-vertex Euclidean distance between the HR target and
// the LR-embedded surface (the size of the correction to learn), normalised
// to mean 1 over the frames. Under the paper's L1 sum every vertex of every
// frame pulls with a unit-size gradient, so frames near rest (corrections of
// 1e-4 cm, a few per sequence) are outvoted by the many large frames and the
// network's response to small inputs stays poor; these weights give them a
// larger share, moving the loss toward a relative error.
// hr, embedded: F × M × 3; returns F.
torch::Tensor relative_frame_weights(const torch::Tensor& hr, const torch::Tensor& embedded, double floor_cm);

// Unnormalised triangle normals (v1 − v0) × (v2 − v0) of B × M × 3 positions: B × F × 3.
torch::Tensor triangle_normals(const torch::Tensor& positions, const torch::Tensor& tris);

// β of eq. 7 at `epoch` of `epochs`: rises geometrically from beta_start at
// the first epoch to beta_end at the last (the paper "gradually increased"
// it from 0.001 to 20 and gives no schedule; a geometric ramp spends equal
// time in every decade).
double beta_schedule(int epoch, int epochs, double beta_start, double beta_end);

}  // namespace facesr
