#pragma once
#include "sr/sr_architecture.h"
#include "sr/sr_geometry.h"

namespace facesr {

// The SIREN coordinate frame of a model (SrArchitecture::coord_center,
// coord_scale) from the rest poses: the centre of the box around the LR and
// HR rest points and its largest half-extent (cm), so a head of any size
// maps to about [-1, 1].
void set_coordinate_frame(SrArchitecture& arch, const SrGeometry& g);

}  // namespace facesr
