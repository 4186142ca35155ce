#pragma once
#include "mesh/tri_mesh.h"

namespace facesr {

// Isotropic remeshing (CGAL Polygon Mesh Processing) to a target edge length:
// turns marching-tetrahedra slivers into well-shaped triangles that TetGen can
// mesh without refining the boundary into needles.
TriMesh remesh_isotropic(const TriMesh& in, double target_edge, int iterations = 3);

// Removes self-intersections without changing connectivity: vertices of
// intersecting triangles and their neighbours are Laplacian-smoothed until
// CGAL finds no intersecting pair. Returns how many vertices moved and the
// largest displacement (cm). Throws if `max_rounds` do not suffice.
struct RepairReport {
  long moved = 0;
  double max_displacement = 0;
  long initial_pairs = 0;
};
RepairReport repair_self_intersections(TriMesh& m, int max_rounds = 60);

struct SurfaceCheck {
  bool closed = false;
  bool self_intersects = false;
  long components = 0;
};
SurfaceCheck check_surface(const TriMesh& m);

}  // namespace facesr
