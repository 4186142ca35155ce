#pragma once
#include <Eigen/Core>

#include "core/types.h"

namespace facesr {

// Mixed Voronoi area of every vertex (Meyer, Desbrun, Schröder and Barr 2003,
// "Discrete differential-geometry operators for triangulated 2-manifolds",
// §3.3 and fig. 4), the diagonal of the mass matrix M the thesis uses in
// eq. (4.2) ("M is the mass matrix representing Voronoi areas around
// vertices"). Per triangle PQR:
//   no obtuse angle: P gets (|PR|^2 cot Q + |PQ|^2 cot R) / 8 (its Voronoi
//                    region inside the triangle), likewise Q and R;
//   obtuse at P:     P gets area / 2, Q and R area / 4 each;
// so the triangle's area is split exactly and the masses sum to the surface
// area. The Voronoi part depends on where the neighbours are, not on how many
// there are, which is why the thesis prefers it to the barycentric third.
// Degenerate triangles (degenerate_triangle()) add nothing; a vertex in no
// other triangle gets mass 0. Units: cm^2.
Eigen::VectorXd voronoi_mass(const Points& V, const Tris& F);

}  // namespace facesr
