// Placeholder while the OpenCL inference kernels are written (issue 6).
#include "core/error.h"
#include "runtime/sr_inference.h"

namespace facesr {

std::unique_ptr<SrInference> make_cl_inference(std::shared_ptr<const SrModel>, const ClInferenceOptions&) {
  throw Error("OpenCL inference is not implemented yet; use the CPU inference");
}

}  // namespace facesr
