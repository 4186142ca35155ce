#include "runtime/rest_subtracted.h"

namespace facesr {
namespace {

class RestSubtracted final : public SrInference {
 public:
  RestSubtracted(std::unique_ptr<SrInference> net, int num_lr, int num_hr) : net_(std::move(net)) {
    // Once at load: with the embedded skip the rest output is still g(0),
    // because the embedding of zero displacement is zero.
    const std::vector<float> zero(3 * size_t(num_lr), 0.0f);
    rest_.resize(3 * size_t(num_hr));
    net_->infer(zero.data(), rest_.data());
  }
  void infer(const float* lr_disp, float* hr_disp) override {
    net_->infer(lr_disp, hr_disp);
    for (size_t i = 0; i < rest_.size(); ++i) hr_disp[i] -= rest_[i];
  }
  std::string device() const override { return net_->device(); }
  std::vector<std::pair<std::string, double>> last_profile() const override { return net_->last_profile(); }

 private:
  std::unique_ptr<SrInference> net_;
  std::vector<float> rest_;
};

}  // namespace

std::unique_ptr<SrInference> subtract_rest_output(std::unique_ptr<SrInference> net, const SrModel& model) {
  if (!model.arch.zero_rest) return net;
  return std::make_unique<RestSubtracted>(std::move(net), model.num_lr, model.num_hr);
}

}  // namespace facesr
