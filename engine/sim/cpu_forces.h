#pragma once
// CPU reference of the simulation energy, its gradient and its Hessian
// (Eigen/OpenMP, double precision). The OpenCL kernels evaluate the same
// functions from cl/fsr_material.h and are tested against this.
#include <vector>

#include "sim/controls.h"
#include "sim/sim_model.h"

namespace facesr {

// Per-tet activation: the activation of the tet's muscle, 0 for flesh.
std::vector<double> tet_activations(const SimModel& m, const FrameInputs& in);

// Total energy (kPa·cm³): elastic + fibre, track springs, point springs, sphere penalties.
double total_energy(const SimModel& m, const FrameInputs& in, const std::vector<double>& tet_alpha,
                    const std::vector<double>& x);

// ∇E at x for every node (node × 3); bone nodes included (callers mask them).
void energy_gradient(const SimModel& m, const FrameInputs& in, const std::vector<double>& tet_alpha,
                     const std::vector<double>& x, std::vector<double>& g);

// Hessian at x in element form: dP/dF per tet and a 3x3 per surface vertex.
struct ElementHessian {
  std::vector<double> C;      // tet × 81
  std::vector<double> surf;   // vertex × 9
  std::vector<double> diag;   // node × 9, diagonal blocks of the assembled Hessian
};
void element_hessian(const SimModel& m, const FrameInputs& in, const std::vector<double>& tet_alpha,
                     const std::vector<double>& x, bool definiteness_fix, ElementHessian& H);
// y = K dx (node × 3), assembled by per-node gathers over the incidence slots.
void hessian_product(const SimModel& m, const ElementHessian& H, const std::vector<double>& dx,
                     std::vector<double>& y);

int count_inverted(const SimModel& m, const std::vector<double>& x);

}  // namespace facesr
