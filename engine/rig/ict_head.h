#pragma once
#include <string>

#include "rig/head_source.h"

namespace facesr {

// Loads an ICT FaceKit folder (generic_neutral_mesh.obj, one OBJ per
// expression of the same topology, vertex_indices.json). Vertex ranges are
// those of the FaceKit layout (see the data folder's README). The neck cut,
// the only hole of the skin + mouth + eye-socket surface, is capped with a
// fan so the skin bounds a volume.
HeadSource load_ict_head(const std::string& folder, bool verbose);

}  // namespace facesr
