#pragma once
#include <string>

#include "mesh/tri_mesh.h"

namespace facesr {

// Reads vertices and faces of a Wavefront OBJ (polygons fan-triangulated).
// Written by hand rather than with tinyobjloader because the rig builder
// needs strict validation with line numbers (NaN/inf coordinates, indices out
// of range, malformed rows) and reads 56 × 2.5 MB ICT files, where a minimal
// position-only parser is several times faster.
TriMesh read_obj(const std::string& path);
// Only vertex positions (for blendshapes of known topology).
Points read_obj_vertices(const std::string& path);
void write_obj(const std::string& path, const Points& V, const Tris& F);

}  // namespace facesr
