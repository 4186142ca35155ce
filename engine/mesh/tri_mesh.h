#pragma once
#include <vector>

#include "core/types.h"

namespace facesr {

struct TriMesh {
  Points V;  // vertex positions (cm)
  Tris F;    // triangles, counter-clockwise seen from outside
};

// Area-weighted vertex normals (unit length; zero for isolated vertices).
Points vertex_normals(const Points& V, const Tris& F);
// Closed loops of boundary edges, each as an ordered vertex list.
std::vector<std::vector<int>> boundary_loops(const Tris& F);
// Unique undirected edges (i < j).
std::vector<std::pair<int, int>> unique_edges(const Tris& F);
// Connected component of each triangle (triangles sharing a vertex are
// connected); `count` receives the number of components.
std::vector<int> face_components(const Tris& F, long num_vertices, int& count);
// Axis-aligned bounding box of V.
void bounding_box(const Points& V, Vec3& lo, Vec3& hi);

}  // namespace facesr
