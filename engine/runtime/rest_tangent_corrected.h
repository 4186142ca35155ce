#pragma once
// A model's rest tangents (sr/rest_tangents.h) added on the host after any
// inference implementation, as rest_subtracted.h does for zero_rest.
#include <memory>

#include "runtime/sr_inference.h"

namespace facesr {

// Returns `net` itself when the model has no rest tangents.
std::unique_ptr<SrInference> add_rest_tangents(std::unique_ptr<SrInference> net, const SrModel& model);

}  // namespace facesr
