#pragma once
#include <vector>

#include "sr/sr_architecture.h"
#include "sr/sr_geometry.h"

namespace facesr {

// The inputs u_ij = [x^H_j, x^L_i, ‖x^L_i − x^H_j‖] (paper eq. 2) of the
// upsampling weight SIREN for every HR vertex j and each of its upsample_k
// neighbours i, in the architecture's normalised coordinates: M × K × 7.
// x^H is the HR rest vertex in the LR rest frame (the lip-separating
// predeformation, where the neighbourhoods were found) when the geometry has
// it, so x^H and x^L are comparable.
std::vector<float> upsample_inputs(const SrArchitecture& arch, const SrGeometry& g);

}  // namespace facesr
