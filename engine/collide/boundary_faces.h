#pragma once
#include "mesh/tet_mesh.h"

namespace facesr {

// Faces that belong to exactly one tetrahedron, oriented with the normal
// pointing out of the mesh (away from the tet's fourth vertex).
Tris boundary_faces(const TetMesh& m);

}  // namespace facesr
