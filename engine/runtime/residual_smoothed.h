#pragma once
// A model's residual smoothing (sr/residual_smoothing.h) on the host after
// any inference implementation, before its near-rest correctives
// (rest_corrected.h), as rest_subtracted.h does for zero_rest.
#include <memory>

#include "runtime/sr_inference.h"

namespace facesr {

// Returns `net` itself when the model has none.
std::unique_ptr<SrInference> smooth_residual(std::unique_ptr<SrInference> net, const SrModel& model);

}  // namespace facesr
