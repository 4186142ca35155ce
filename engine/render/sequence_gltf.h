#pragma once
#include <string>
#include <vector>

#include "perf/sequence_io.h"
#include "rig/rig.h"

namespace facesr {

// Most frames one glTF file holds: each frame is a morph target, and the
// animation's weight track grows with frames².
constexpr int kMaxGltfFrames = 1000;

// Writes the chosen frames (all when `frames` is empty) of a sequence's face
// surface as a self-contained glTF 2.0 file (.gltf JSON, buffer embedded as
// base64). Layout:
//   - one mesh: rig.surface_tris over the first chosen frame's positions
//     (POSITION, NORMAL, u32 indices), one morph target per later chosen frame
//     holding its POSITION offset from the first;
//   - one node with scale 0.01: positions stay in cm, as everywhere in
//     facesr, and the node converts them to glTF's metres;
//   - one animation "sequence" with STEP interpolation of the morph weights:
//     at each frame's time (seconds from the first chosen frame) its target
//     has weight 1 and all others 0.
// "asset.extras" records units "cm", the rig name, the frame indices and fps.
// Throws Error on a surface/rig mismatch, frame indices out of range or more
// than kMaxGltfFrames frames; written atomically.
void write_sequence_gltf(const Rig& rig, const Sequence& seq, const std::string& path,
                         const std::vector<int>& frames = {});

// Standard base64 (RFC 4648, with padding), for glTF data URIs.
std::string base64_encode(const void* data, size_t size);

}  // namespace facesr
