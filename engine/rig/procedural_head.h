#pragma once
#include "rig/head_source.h"

namespace facesr {

struct ProceduralOptions {
  double grid_h = 0.2;     // cm, sampling of the implicit head
  double edge = 0.45;      // cm, target skin edge length after remeshing
};

// A parametric head built from smooth-blended ellipsoids: cranium, face,
// nose, cheeks, chin, lips around a mouth slit opening into a mouth cavity,
// upper and lower teeth arches in the cavity, a neck cut flat at the bottom.
// Blendshapes (ARKit names) are analytic displacement fields; the jaw shapes
// are exact rigid motions of the teeth and linear-blend-skinned flesh.
HeadSource make_procedural_head(const ProceduralOptions& opt);

}  // namespace facesr
