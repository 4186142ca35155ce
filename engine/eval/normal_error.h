#pragma once
#include "core/types.h"

namespace facesr {

// Mean angle (degrees) between corresponding vertex normals of two surfaces
// over the same triangles: per vertex the angle between the area-weighted
// vertex normals (vertex_normals() in mesh/tri_mesh.h) of the reference and
// of the test surface, averaged over the vertices that have a normal on both
// (vertices in no non-degenerate triangle are left out). Vertex normals, not
// face normals, because shading (and so what a viewer sees of a wrong
// surface) interpolates them. Unlike DAME this is not invariant under a
// rotation of one mesh: a test surface rotated by alpha scores alpha.
// Returns 0 when no vertex has a normal; throws Error when the vertex counts
// differ.
double mean_normal_angle_deg(const Points& reference, const Points& test, const Tris& F);

}  // namespace facesr
