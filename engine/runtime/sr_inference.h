#pragma once
// Super-resolution inference at run time, without LibTorch: LR node
// displacements in, HR surface displacements out, for one frame, with a
// model file's network (kind "sr"). Two implementations of the same
// arithmetic: OpenCL kernels (cl/sr_infer.cl, the runtime's) and a plain C++
// reference (for parity checks and as a fallback).
#include <memory>
#include <string>
#include <vector>

#include "compute/cl_device.h"
#include "sr/sr_model.h"

namespace facesr {

// Load-time constants of a model shared by both implementations: the exact
// algebraic shortcuts of the network. The upsampling weights depend only on
// rest-pose coordinates, so they are computed once (a fixed M × K sparse
// matrix).
struct SrInferencePlan {
  int N = 0, M = 0, K = 0;
  std::vector<float> up_weight;  // M × K softmax weights w_jq
  std::vector<int32_t> up_index; // M × K LR node per weight
  std::vector<float> pe;         // N × pe_dim positional encoding
};
SrInferencePlan make_inference_plan(const SrModel& model);
// The plan is the costliest thing an inference builds (the weight SIREN
// over every upsampling pair): contexts on one model share one (RuntimeModel).
using SharedInferencePlan = std::shared_ptr<const SrInferencePlan>;

class SrInference {
 public:
  virtual ~SrInference() = default;
  // lr_disp: N × 3 (cm), hr_disp: M × 3 (cm).
  virtual void infer(const float* lr_disp, float* hr_disp) = 0;
  virtual std::string device() const = 0;
  // Per-stage milliseconds of the last infer() when profiling is on (empty otherwise).
  virtual std::vector<std::pair<std::string, double>> last_profile() const { return {}; }
};

// Throws Error for a model of kind other than "sr". `plan` is the model's
// make_inference_plan (made here when null).
std::unique_ptr<SrInference> make_cpu_inference(std::shared_ptr<const SrModel> model, SharedInferencePlan plan = nullptr);

enum class ClKernels { Auto, Simd, Tiled };
enum class ClKnn { Auto, Full, Simd, Pruned, Symmetric };

struct ClInferenceOptions {
  compute::DeviceSelector device;
  bool profile = false;  // wait after each stage and time it (slower)
  // Feature-space k-NN, every variant exact (the same neighbours in the same
  // order): Auto picks Symmetric on CPU devices and Full on GPUs; Full scans every
  // node per work-item; Simd scans 32 candidates per step for 8 queries;
  // Pruned walks the nodes sorted along the features' principal direction;
  // Symmetric (Auto on CPU devices) computes each pair's distance once, for
  // both of its nodes, bounded by last frame's neighbours.
  ClKnn knn = ClKnn::Auto;
  // Symmetric: candidates kept per node below its bound; a node with more
  // (its features moved far since the last frame) is redone by a full scan.
  int knn_list = 64;
  // Dense layers and upsampling: Auto picks the 16-wide Simd kernels on CPU
  // devices and the local-memory Tiled ones on GPUs; either runs anywhere
  // (so that tests cover the GPU path on a CPU device).
  ClKernels kernels = ClKernels::Auto;
  // Simd dense layers: outputs per work-item. 0 (automatic) or 32: 32 where
  // the layer's padded width is a multiple of 32, else 16; 16: always 16.
  // The results are bit-identical either way.
  int dense_width = 0;
};
std::unique_ptr<SrInference> make_cl_inference(std::shared_ptr<const SrModel> model,
                                               const ClInferenceOptions& opt = {}, SharedInferencePlan plan = nullptr);

}  // namespace facesr
