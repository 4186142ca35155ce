#pragma once
#include <string>
#include <vector>

#include "mesh/tet_mesh.h"
#include "mesh/tri_mesh.h"

namespace facesr {

struct TetgenOptions {
  double radius_edge = 1.6;     // TetGen -q bound on circumradius / shortest edge
  double min_dihedral = 10.0;   // TetGen -q second bound (degrees)
  double max_volume = 0;        // -a bound in cm³; 0 = none
  bool preserve_boundary = true;  // -Y: boundary triangles kept as given (skin conforms exactly)
  // -S bound on added (Steiner) points, as a multiple of the input points; 0 =
  // none. Quality refinement that needs more than this does not converge on
  // the input (seen on a bone surface of sliver triangles) and would
  // otherwise run for hours; reaching the bound is an error, not a mesh.
  double max_steiner_per_input = 40;
};

// Conforming Delaunay tetrahedralisation of the volume bounded by a closed,
// non-self-intersecting triangle surface (which may have several shells).
// `holes` are points inside cavities that must stay empty (e.g. bone).
// Input vertices keep their indices; Steiner points follow. Tets come out
// positively oriented.
TetMesh tetrahedralize(const TriMesh& boundary, const std::vector<Vec3>& holes,
                       const TetgenOptions& opt);

}  // namespace facesr
