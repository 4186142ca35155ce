#pragma once
#include <nlohmann/json.hpp>

#include "rig/rig.h"

namespace facesr {

// Human- and script-readable statistics of a rig (sizes, mesh quality,
// anatomy, jaw fit), e.g. for `facesr rig info` and build reports. Lengths in
// the rig's units (cm), angles in degrees.
nlohmann::json rig_summary(const Rig& rig);

}  // namespace facesr
