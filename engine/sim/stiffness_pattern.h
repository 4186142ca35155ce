#pragma once
#include <cstdint>
#include <vector>

#include "sim/sim_model.h"

namespace facesr {

// The assembled stiffness matrix K of a SimModel: its sparsity in 3x3 blocks
// over the free nodes (block rows by node, bone rows and columns left out:
// the solver's bone DOFs are fixed, so their rows are zero and their
// columns only ever meet zeros), and, for every block, where its value comes
// from, so that a gather per block row assembles K without atomics.
//
// Sources of block (v, u):
// - tet blocks: each tet with corners k, m at nodes v, u adds its block K_km
//   (cl/fsr_material_body.h tet_blocks stores the ten k ≤ m); a ref is
//   2 (10 t + pair) + 1 when the stored block is K_mk and must be transposed;
// - surface points: each embedded surface vertex with corners a, b at v, u
//   adds w_a w_b H_i (H_i its 3x3 Hessian, i its index in inc_all.vertices);
//   a ref is 16 i + 4 a + b;
// - the track springs alone: `track` holds Σ_v k_v w_a w_b per block (times
//   the identity), which is all that frames without point springs or
//   spheres need instead of the surface refs.
struct StiffnessPattern {
  std::vector<int32_t> row_offset;  // node + 1
  std::vector<int32_t> col;         // block → its column node
  std::vector<int32_t> diag;        // node → its diagonal block, −1 for bone nodes
  std::vector<int32_t> tet_offset, tet_ref;    // block + 1, refs
  std::vector<int32_t> surf_offset, surf_ref;  // block + 1, refs
  std::vector<double> track;                   // block
  size_t num_blocks() const { return col.size(); }
};

StiffnessPattern make_stiffness_pattern(const SimModel& m);

}  // namespace facesr
