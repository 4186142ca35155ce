#pragma once
#include <map>
#include <string>
#include <vector>

#include "core/types.h"

namespace facesr {

// Semantic landmark names used by the muscle specification, from the
// Multi-PIE 68-point layout (0-based): sides are named by the subject's left
// (+x) and right (-x). Rings: "eye_ring_L_0".."_5", "eye_ring_R_0".."_5",
// "mouth_ring_0".."_11" (outer lip contour).
std::map<std::string, int> landmarks_from_multipie68(const std::vector<int>& idx68, const Points& V);

}  // namespace facesr
