#pragma once
// MLS baseline (paper appendix A.3): per HR vertex and per displacement
// component, a degree-2 moving least-squares fit over the same upsample_k
// geodesic neighbours as the network, Gaussian weights of the geodesic
// distance, basis re-centred on the HR vertex so the value is c0.
#include <memory>
#include <vector>

#include "sr/sr_geometry.h"

namespace facesr {

class MlsBaseline {
 public:
  MlsBaseline(const SrGeometry& g, double sigma_cm);
  ~MlsBaseline();
  MlsBaseline(MlsBaseline&&) noexcept;
  MlsBaseline& operator=(MlsBaseline&&) noexcept;

  // lr_disp: N × 3 (cm) → hr_disp: M × 3 (cm).
  void apply(const float* lr_disp, float* hr_disp) const;
  double sigma_cm() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
