#pragma once
// C++ access to the shared Teran material (cl/fsr_material.h): parameters in
// engine units and the C functions themselves.
#include <cmath>

#include "fsr_material.h"

namespace facesr {

// Soft-tissue constants, lengths in cm and stresses in kPa. Defaults follow
// the ranges reported for facial soft tissue (shear modulus of a few kPa,
// Poisson ratio ≈ 0.49) and give facial muscles a peak stress that moves the
// skin by about a centimetre; all are per unit volume or area, so LR and HR
// meshes behave alike in bulk (resolution invariance, paper §4).
struct MaterialParams {
  double mu10 = 1.5;         // kPa
  double mu01 = 0.5;         // kPa
  double kappa = 200;        // kPa
  double j_min = 0.25;       // deviatoric J floor
  double sigma_max = 40;     // kPa, peak active fibre stress
  double p1 = 0.05, p2 = 6.6;  // passive fibre curve (Blemker 2005)
  double stretch_lin = 1.4;  // passive curve turns linear beyond this stretch
  double track_stiffness = 5;  // kPa/cm: spring force per cm offset per cm² of skin

  double shear_modulus() const { return 2 * (mu10 + mu01); }
  fsr_material to_c() const {
    return fsr_material{mu10, mu01, kappa, j_min, sigma_max, p1, p2, stretch_lin};
  }
};

}  // namespace facesr
