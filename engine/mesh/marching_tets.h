#pragma once
#include <vector>

#include "mesh/grid.h"
#include "mesh/tri_mesh.h"

namespace facesr {

// Zero level set of a grid field (negative inside) as a closed, welded,
// outward-oriented triangle mesh. Each cube is split into the 6 Kuhn
// tetrahedra of the Freudenthal triangulation, which is consistent across
// cubes, so the surface is watertight without case tables or ambiguity.
TriMesh marching_tets(const Grid& grid, const std::vector<float>& field);

}  // namespace facesr
