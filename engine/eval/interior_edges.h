#pragma once
#include <array>
#include <vector>

#include "core/types.h"

// The edges of a triangle surface that carry an oriented dihedral angle: those
// shared by exactly two triangles that traverse the edge in opposite
// directions. Border edges (one triangle), non-manifold edges (three or more)
// and edges between inconsistently oriented triangles have no well-defined
// oriented angle and are left out (and counted). Depends only on the
// connectivity, so it is computed once per rig and reused for every frame.
namespace facesr {

struct InteriorEdges {
  // Per interior edge: i, j, a, b where triangle (i, j, a) traverses i -> j
  // and triangle (j, i, b) traverses j -> i (both counter-clockwise seen from
  // outside); a and b are the vertices opposite the edge.
  std::vector<std::array<int32_t, 4>> quads;
  std::vector<std::array<int32_t, 2>> faces;  // the triangles (i, j, a) and (j, i, b)
  long border = 0;                            // edges with one triangle
  long non_manifold = 0;                      // edges with three or more triangles
  long flipped = 0;                           // two triangles traversing the edge the same way

  long size() const { return long(quads.size()); }
};

// Throws Error when a triangle refers to a vertex outside [0, num_vertices)
// or repeats a vertex.
InteriorEdges interior_edges(const Tris& F, long num_vertices);

}  // namespace facesr
