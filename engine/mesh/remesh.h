#pragma once
#include "mesh/tri_mesh.h"

namespace facesr {

// Isotropic remeshing (CGAL Polygon Mesh Processing) to a target edge length:
// turns marching-tetrahedra slivers into well-shaped triangles that TetGen can
// mesh without refining the boundary into needles.
TriMesh remesh_isotropic(const TriMesh& in, double target_edge, int iterations = 3);

struct SurfaceCheck {
  bool closed = false;
  bool self_intersects = false;
  long components = 0;
};
SurfaceCheck check_surface(const TriMesh& m);

}  // namespace facesr
