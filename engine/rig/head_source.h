#pragma once
#include <map>
#include <string>
#include <vector>

#include "mesh/tri_mesh.h"

namespace facesr {

// Per-vertex labels of the closed skin surface.
enum class SkinRegion : uint8_t { Face = 0, Head = 1, Mouth = 2, EyeSocket = 3, NeckCap = 4 };

// What the rig builder needs from a head, whatever made it (the ICT FaceKit
// folder or the procedural generator). Units: centimetres, +y up, +z out of
// the face, +x toward the subject's left.
struct HeadSource {
  std::string name;
  // Closed, outward-oriented surface bounding the head: skin, mouth lining,
  // eye sockets, and a cap over the neck cut.
  TriMesh skin;
  std::vector<SkinRegion> region;  // per skin vertex
  // Vertices (into skin) of the face surface that the engine outputs.
  std::vector<int> face_vertices;
  // Linear blendshape model on skin vertices: target = V + Σ w_i * delta_i.
  std::vector<std::string> blendshape_names;
  std::vector<Points> blendshape_deltas;
  // Rigid parts inside the mouth; the lower ones move with the jaw.
  TriMesh teeth_upper, teeth_lower;
  // Lower-teeth vertex positions in each jaw blendshape (jawOpen, jawLeft,
  // ...), from which the jaw's rigid motion is fitted.
  std::vector<std::pair<std::string, Points>> jaw_shape_lower_teeth;
  // Named landmarks on the skin (see landmarks.h for the names).
  std::map<std::string, int> landmarks;  // name -> skin vertex
};

}  // namespace facesr
