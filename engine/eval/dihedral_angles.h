#pragma once
#include <vector>

#include "eval/interior_edges.h"

namespace facesr {

// Oriented dihedral angle (radians, in (-pi, pi]) of every interior edge of
// the surface V: the signed angle that turns the normal of (i, j, a) into the
// normal of (j, i, b) about the edge direction i -> j. Positive where the
// surface is convex (bends away from its outward normals), negative where it
// is concave, 0 where flat; a degenerate (zero-area) triangle counts as flat.
// The sign is what makes the angle "oriented": a ridge pushed into a valley
// of the same sharpness changes sign, so its error is twice the angle, not 0.
std::vector<double> oriented_dihedral_angles(const Points& V, const InteriorEdges& edges);

}  // namespace facesr
