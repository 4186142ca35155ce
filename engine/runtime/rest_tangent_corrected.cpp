#include "runtime/rest_tangent_corrected.h"

namespace facesr {
namespace {

class RestTangentCorrected final : public SrInference {
 public:
  RestTangentCorrected(std::unique_ptr<SrInference> net, const SrModel& m)
      : net_(std::move(net)), correction_(m.rest_tangents, m.num_lr, m.num_hr) {}
  void infer(const float* lr_disp, float* hr_disp) override {
    net_->infer(lr_disp, hr_disp);
    correction_.apply(lr_disp, hr_disp);
  }
  std::string device() const override { return net_->device(); }
  std::vector<std::pair<std::string, double>> last_profile() const override { return net_->last_profile(); }

 private:
  std::unique_ptr<SrInference> net_;
  RestTangentCorrection correction_;
};

}  // namespace

std::unique_ptr<SrInference> add_rest_tangents(std::unique_ptr<SrInference> net, const SrModel& model) {
  if (model.rest_tangents.empty()) return net;
  return std::make_unique<RestTangentCorrected>(std::move(net), model);
}

}  // namespace facesr
