#pragma once
// The CPU reference's Hessian assembled into 3x3 blocks over the free nodes
// (the pattern of sim/stiffness_pattern.h), for the PCG products.
//
// Why: the element-form product (hessian_product) re-reads the 81 values of
// dP/dF per tet and goes through a slot buffer on every CG iteration, about
// 170 MB of memory traffic per product on the ICT HR mesh (201k tets); perf
// put three quarters of an HR frame there. The assembled matrix is about
// 47 MB, built once per Newton iteration, and each product streams it once.
#include <vector>

#include "sim/cpu_forces.h"
#include "sim/stiffness_pattern.h"

namespace facesr {

struct AssembledStiffness {
  StiffnessPattern pattern;
  std::vector<double> blocks;  // block × 9, row-major 3x3
  std::vector<double> tet_blocks;  // scratch: tet × 90 (fsr_tet_blocks)
};

// The pattern only; assemble_stiffness fills the values.
AssembledStiffness make_assembled_stiffness(const SimModel& m);

// K from the element Hessian (tets and surface points; bone rows and
// columns left out, as the solver never moves bone nodes).
void assemble_stiffness(const SimModel& m, const ElementHessian& H, AssembledStiffness& K);

// y = K dx (node × 3); bone nodes get 0. Equals hessian_product on the free
// nodes up to rounding.
void stiffness_product(const AssembledStiffness& K, const std::vector<double>& dx, std::vector<double>& y);

}  // namespace facesr
