#pragma once
// Input checks shared by the interpolation baselines.
#include <cstddef>
#include <string>
#include <vector>

namespace facesr {

// Throws Error naming `what` and the first non-finite node of an n × 3 frame.
void require_finite_frame(const float* v, int n, const std::string& what);
// Throws Error unless `v` holds n × 3 values.
void require_frame_size(const std::vector<float>& v, int n, const std::string& what);

}  // namespace facesr
