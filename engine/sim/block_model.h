#pragma once
#include "sim/sim_model.h"

namespace facesr {

// A synthetic lattice slab for benchmarks and convergence studies: nx·ny·nz
// cubic cells of `cell` cm (6 Kuhn tets each), bottom layer fixed like the
// cranium, top layer moving like the jaw, one muscle with fibres along +y
// filling the middle third, and the top face as the tracked "surface".
// Sizes are chosen by the caller to sweep the tet count.
SimModel make_block_model(int nx, int ny, int nz, double cell, const MaterialParams& material = {});

}  // namespace facesr
