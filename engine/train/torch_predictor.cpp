#include "train/torch_predictor.h"

#include <algorithm>

#include "core/error.h"
#include "sr/residual_smoothing.h"
#include "sr/rest_correctives.h"
#include "train/model_export.h"
#include "train/sr_network.h"
#include "train/vae_network.h"

namespace facesr {

struct TorchPredictor::Impl {
  SrNetwork sr{nullptr};
  VaeNetwork vae{nullptr};
  int64_t N = 0;
  std::unique_ptr<ResidualSmoother> smoother;  // null: none
  std::unique_ptr<RestCorrection> correction;  // null: none
};

TorchPredictor::TorchPredictor(const SrModel& m) : impl_(std::make_unique<Impl>()) {
  impl_->N = m.num_lr;
  if (!m.residual_smoothing.empty())
    impl_->smoother = std::make_unique<ResidualSmoother>(m.residual_smoothing, m.geometry);
  if (!m.rest_correctives.empty())
    impl_->correction = std::make_unique<RestCorrection>(m.rest_correctives, m.num_lr, m.num_hr);
  if (m.arch.kind == "sr") {
    impl_->sr = SrNetwork(m.arch, m.geometry);
  } else {
    impl_->vae = VaeNetwork(m.arch, m.num_lr, m.num_hr);
  }
  import_parameters(m, module());
  module().eval();
}

TorchPredictor::~TorchPredictor() = default;

torch::nn::Module& TorchPredictor::module() {
  return impl_->sr ? static_cast<torch::nn::Module&>(*impl_->sr) : *impl_->vae;
}

torch::Tensor TorchPredictor::predict(const torch::Tensor& lr, int batch) {
  require(lr.dim() == 3 && lr.size(1) == impl_->N && lr.size(2) == 3,
          "model input must be F × " + std::to_string(impl_->N) + " × 3 LR displacements");
  require(batch >= 1, "predict: batch must be at least 1");
  torch::NoGradGuard no_grad;
  std::vector<torch::Tensor> out;
  for (int64_t b = 0; b < lr.size(0); b += batch) {
    const auto x = lr.narrow(0, b, std::min<int64_t>(batch, lr.size(0) - b)).to(torch::kFloat32);
    out.push_back(impl_->sr ? impl_->sr->forward(x).hr_disp : impl_->vae->forward(x, false).hr_disp);
  }
  torch::Tensor y = torch::cat(out, 0);
  if (impl_->smoother || impl_->correction) {
    // The same host arithmetic as the runtime's (runtime/residual_smoothed.h,
    // runtime/rest_corrected.h), in that order.
    y = y.to(torch::kCPU).contiguous();
    const auto x = lr.to(torch::kCPU, torch::kFloat32).contiguous();
    for (int64_t f = 0; f < y.size(0); ++f) {
      if (impl_->smoother) impl_->smoother->apply(x[f].data_ptr<float>(), y[f].data_ptr<float>());
      if (impl_->correction) impl_->correction->apply(x[f].data_ptr<float>(), y[f].data_ptr<float>());
    }
  }
  return y;
}

}  // namespace facesr
