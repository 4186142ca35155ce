#pragma once
#include <vector>

#include "rig/rig.h"

namespace facesr {

// Lattice cell and Kuhn tetrahedron (0..5) containing p. The six Kuhn tets
// of a cube are ordered by which local coordinate is largest, then second.
void lattice_locate(const Lattice& L, const Vec3& p, long& cell, int& kuhn);

// Builds the lattice tet mesh over the given cells (linear cell indices of L):
// shared corner nodes, 6 positively oriented tets per cell, cell-major order.
// tet_of_cell receives, per lattice cell, the index of its first tet or -1.
TetMesh lattice_mesh(const Lattice& L, const std::vector<long>& cells, std::vector<long>& first_tet_of_cell);

}  // namespace facesr
