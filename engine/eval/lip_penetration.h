#pragma once
// Lip contact on a method's face surface (appendix A.5 discusses what the
// LR simulation, which has no contact, leaves to the network): how deep the
// upper lip goes into the lower one and either lip into the teeth, measured
// on the surface a method outputs. The HR reference resolves these contacts
// (to ~0.03 cm, sim/simulator.h); a method that undoes them shows here.
#include <array>
#include <memory>
#include <vector>

#include "core/types.h"
#include "mesh/surface_query.h"
#include "mesh/tri_mesh.h"
#include "rig/rig.h"

namespace facesr {

struct LipPenetrationSetup {
  std::vector<int> upper, lower;  // face-surface vertices of each lip
  Tris upper_tris, lower_tris;    // face-surface triangles with every corner in that lip
  TriMesh teeth_upper, teeth_lower;  // closed meshes, outward normals (lower: in the jaw's rest frame)
  double max_depth_cm = 0.6;      // deeper points count as being on the far side (as the HR collider)
  // Per vertex of upper then lower: already behind the other lip / inside a
  // tooth on the rest surface (lips closed at rest), and so not counted.
  std::vector<uint8_t> rest_lip, rest_teeth;
  // Built once by finish_lip_penetration_setup: the teeth do not deform.
  std::shared_ptr<const SurfaceQuery> teeth_upper_query, teeth_lower_query;
};

struct LipPenetration {
  double lip_cm = 0;    // deepest lip vertex behind the other lip's surface
  double teeth_cm = 0;  // deepest lip vertex inside a tooth
  int lip_vertices = 0, teeth_vertices = 0;  // vertices penetrating
};

// Lips from the rig's landmarks (rig/rig_build.h lip_vertices), its teeth,
// and the rest exclusions from its rest surface.
LipPenetrationSetup lip_penetration_setup(const Rig& rig);
// Builds the teeth queries and fills rest_lip and rest_teeth from the rest
// positions (M × 3, cm); call after setting the other fields by hand.
void finish_lip_penetration_setup(LipPenetrationSetup& s, const Points& rest);

// `surface`: M × 3 positions (cm); jaw: the frame's R (row-major) and t (cm)
// that carry the lower teeth.
LipPenetration lip_penetration(const LipPenetrationSetup& s, const Points& surface, const std::array<float, 12>& jaw);

}  // namespace facesr
