#pragma once
// A model's near-rest correctives (sr/rest_correctives.h) added on the host after any
// inference implementation, as rest_subtracted.h does for zero_rest.
#include <memory>

#include "runtime/sr_inference.h"

namespace facesr {

// Returns `net` itself when the model has none.
std::unique_ptr<SrInference> add_rest_correctives(std::unique_ptr<SrInference> net, const SrModel& model);

}  // namespace facesr
