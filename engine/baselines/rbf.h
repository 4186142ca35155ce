#pragma once
// RBF baseline (paper appendix A.2): Gaussian radial basis functions centred
// on the LR nodes with geodesic distances, weights solved per frame from the
// LR displacements, evaluated at the HR surface vertices.
#include <memory>
#include <vector>

#include "sr/sr_geometry.h"

namespace facesr {

class RbfBaseline {
 public:
  // Builds and factorises once; each frame is then a solve and a product.
  // Distances R (appendix A.2 "geodesically following §3.2"): between an HR
  // vertex and an LR node, the shortest path over the HR surface (hr_rest,
  // hr_tris) from the vertex to the node's mapped vertex (lr_to_hr); between
  // two LR nodes, the same between their mapped vertices. Fallbacks, all
  // Euclidean: to a mapped vertex on another surface component, the straight
  // distance to that vertex (hr_rest); to or between unmapped nodes (N > M),
  // the straight distance in the LR frame (lr_rest, hr_rest_lr_frame) with a
  // mapped node standing at its mapped vertex. These rules make R(i, k) =
  // R(mapped vertex of i, k), so at a mapped vertex the HR field equals the
  // fit Φ W at its node (the LR data itself when μ = 0).
  //
  // Solve: with geodesic distances Φ is strongly indefinite (ICT rig, σ = 1
  // and 2 cm: about a third to a half of its eigenvalues negative, the
  // lowest near -0.4 and -0.6 against a largest of 23 and 43), and near
  // singular, since nodes deep in the flesh map onto surface vertices next to
  // other nodes' vertices with different data. Solving Φ W = D exactly then
  // gives weights that cancel only at the mapped vertices (errors of 3 to 40
  // cm between them on a 0.3 cm smooth field), and a diagonal ridge does not
  // help an indefinite matrix (it moves negative eigenvalues through zero).
  // So W is the Tikhonov-regularised least-squares solution
  //   W = argmin |Φ W − D|² + μ² |W|² = (Φ² + μ²I)⁻¹ Φ D,
  // μ = `regularization` (Φ's entries are ≤ 1, so μ is relative), which is
  // exact interpolation as μ → 0; μ = 0 solves Φ W = D by LU as the paper
  // writes it. Throws Error on an inconsistent geometry (no hr_tris
  // included), σ not finite and > 0, or μ negative or not finite.
  RbfBaseline(const SrGeometry& g, double sigma_cm, double regularization = kRegularization);
  ~RbfBaseline();
  RbfBaseline(RbfBaseline&&) noexcept;
  RbfBaseline& operator=(RbfBaseline&&) noexcept;

  // lr_disp: N × 3 (cm) → hr_disp: M × 3 (cm). Throws Error on a
  // non-finite displacement.
  void apply(const float* lr_disp, float* hr_disp) const;
  double sigma_cm() const;

  // Same, with the sizes checked (N × 3 in, M × 3 out).
  std::vector<float> apply(const std::vector<float>& lr_disp) const;
  // Reciprocal condition number estimate of the factorised matrix
  // (Φ² + μ²I, or Φ when μ = 0), and μ.
  double rcond() const;
  double regularization() const;
  // Stored entries of the M × N evaluation matrix (the rest fell below
  // kDropTolerance) and their fraction of M × N.
  size_t stored_entries() const;
  double stored_fraction() const;

  // Φ entries below this are dropped from the evaluation matrix (they are
  // exp(-R²/σ²) ≤ 1, so this is relative to the largest).
  static constexpr double kDropTolerance = 1e-7;
  // Default μ; fit_rbf_params chooses it with σ on training frames. On the
  // ICT rig, for a smooth 0.3 cm field, the mean HR error at σ = 1, 2, 4 cm
  // was 0.51, 0.32, 0.27 cm with μ = 1e-3; 0.15, 0.12, 0.10 with 1e-2; and
  // 0.067, 0.060, 0.057 with 1e-1 (MLS: 0.050; μ = 0 at σ = 2: 3.2).
  static constexpr double kRegularization = 1e-1;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
