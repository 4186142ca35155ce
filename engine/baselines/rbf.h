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
  // Builds and factorises Φ once; each frame is then a solve and a product.
  // Distances R (appendix A.2 "geodesically following §3.2"): between an HR
  // vertex and an LR node, the shortest path over the HR surface (hr_rest,
  // hr_tris) from the vertex to the node's mapped vertex (lr_to_hr); between
  // two LR nodes, the same between their mapped vertices. Fallbacks, all
  // Euclidean: to a mapped vertex on another surface component, the straight
  // distance to that vertex (hr_rest); to or between unmapped nodes (N > M),
  // the straight distance in the LR frame (lr_rest, hr_rest_lr_frame) with a
  // mapped node standing at its mapped vertex. These rules make R(i, k) =
  // R(mapped vertex of i, k), so the HR field equals the LR data at the
  // mapped vertices. Throws Error on an inconsistent geometry (no hr_tris
  // included) or σ not finite and > 0.
  RbfBaseline(const SrGeometry& g, double sigma_cm);
  ~RbfBaseline();
  RbfBaseline(RbfBaseline&&) noexcept;
  RbfBaseline& operator=(RbfBaseline&&) noexcept;

  // lr_disp: N × 3 (cm) → hr_disp: M × 3 (cm). Throws Error on a
  // non-finite displacement.
  void apply(const float* lr_disp, float* hr_disp) const;
  double sigma_cm() const;

  // Same, with the sizes checked (N × 3 in, M × 3 out).
  std::vector<float> apply(const std::vector<float>& lr_disp) const;
  // Reciprocal condition number estimate of the factorised Φ (+ ridge).
  double rcond() const;
  // Stored entries of the M × N evaluation matrix (the rest fell below
  // kDropTolerance) and their fraction of M × N.
  size_t stored_entries() const;
  double stored_fraction() const;

  // Φ entries below this are dropped from the evaluation matrix (they are
  // exp(-R²/σ²) ≤ 1, so this is relative to the largest).
  static constexpr double kDropTolerance = 1e-7;
  // Added to Φ's diagonal before factorising: with geodesic distances Φ is
  // not guaranteed positive definite, and Gaussian Φ gets close to singular
  // for σ large against the node spacing; the ridge bounds the weights at
  // the cost of an interpolation residual of kRidge · |W| at the nodes.
  static constexpr double kRidge = 1e-9;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
