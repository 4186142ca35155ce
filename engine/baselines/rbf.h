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
  RbfBaseline(const SrGeometry& g, double sigma_cm);
  ~RbfBaseline();
  RbfBaseline(RbfBaseline&&) noexcept;
  RbfBaseline& operator=(RbfBaseline&&) noexcept;

  // lr_disp: N × 3 (cm) → hr_disp: M × 3 (cm).
  void apply(const float* lr_disp, float* hr_disp) const;
  double sigma_cm() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
