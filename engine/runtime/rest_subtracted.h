#pragma once
// Architecture flag zero_rest: every frame's output minus the network's
// output at the rest input (zero displacement), so rest maps exactly to
// rest. One wrapper for every implementation, which stays the plain network.
#include <memory>

#include "runtime/sr_inference.h"

namespace facesr {

// Returns `net` itself when the model has no zero_rest.
std::unique_ptr<SrInference> subtract_rest_output(std::unique_ptr<SrInference> net, const SrModel& model);

}  // namespace facesr
