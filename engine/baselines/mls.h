#pragma once
// MLS baseline (paper appendix A.3): per HR vertex and per displacement
// component, a degree-2 moving least-squares fit over the same upsample_k
// geodesic neighbours as the network, Gaussian weights of the geodesic
// distance, basis re-centred on the HR vertex so the value is c0.
#include <cstdint>
#include <memory>
#include <vector>

#include "sr/sr_geometry.h"

namespace facesr {

class MlsBaseline {
 public:
  // Precomputes, per HR vertex j and component c, the weights a with
  // Δ_c(j) = Σ_s a_s Δ_c(up_index[j][s]) (the c0 of the fit; they sum to 1).
  // Basis t = (LR rest coordinate c of the neighbour) − (coordinate c of
  // vertex j in the LR frame, hr_rest_lr_frame or hr_rest if absent).
  // Guard: the 3 × 3 normal matrix (in t scaled by its largest |t|) must
  // have reciprocal condition ≥ kMinRcond, else the fit drops to degree 1
  // (same test on 2 × 2), else to degree 0, the weighted mean. On the LR
  // lattice the neighbours' coordinates take few distinct values, so this
  // happens: 840 of the 28,227 (vertex, component) fits on the ICT rig drop
  // to degree 1, none to 0. Weights are Gaussian in up_dist, shifted by the
  // nearest one (the fit is invariant to a common scale) so that they cannot
  // all underflow. Throws Error on an inconsistent geometry or σ not finite
  // and > 0.
  MlsBaseline(const SrGeometry& g, double sigma_cm);
  ~MlsBaseline();
  MlsBaseline(MlsBaseline&&) noexcept;
  MlsBaseline& operator=(MlsBaseline&&) noexcept;

  // lr_disp: N × 3 (cm) → hr_disp: M × 3 (cm). Throws Error on a
  // non-finite displacement.
  void apply(const float* lr_disp, float* hr_disp) const;
  double sigma_cm() const;

  // Same, with the sizes checked (N × 3 in, M × 3 out).
  std::vector<float> apply(const std::vector<float>& lr_disp) const;
  // Degree of the fit used per HR vertex and component (M × 3: 0, 1 or 2).
  const std::vector<uint8_t>& degree() const;
  // Weights per HR vertex, component and neighbour slot (M × 3 × upsample_k).
  const std::vector<float>& weights() const;

  static constexpr double kMinRcond = 1e-6;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
