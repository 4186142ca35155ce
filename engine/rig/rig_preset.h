#pragma once
#include <string>

#include "rig/rig_build.h"

namespace facesr {

// Named build settings: "default" leaves the options as they are; "coarse"
// is a small rig for unit tests, CI and minutes-long demos (coarse grids,
// big cells, no HR/LR ratio bound). Error for any other name.
void apply_rig_preset(RigBuildOptions& o, const std::string& preset);

}  // namespace facesr
