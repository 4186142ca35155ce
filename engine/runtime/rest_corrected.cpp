#include "runtime/rest_corrected.h"

#include <chrono>

namespace facesr {
namespace {

class RestCorrected final : public SrInference {
 public:
  RestCorrected(std::unique_ptr<SrInference> net, const SrModel& m)
      : net_(std::move(net)), correction_(m.rest_correctives, m.num_lr, m.num_hr) {}
  void infer(const float* lr_disp, float* hr_disp) override {
    net_->infer(lr_disp, hr_disp);
    const auto t0 = std::chrono::steady_clock::now();
    correction_.apply(lr_disp, hr_disp);
    ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  std::string device() const override { return net_->device(); }
  // The network's stages (empty unless profiling is on), then this one.
  std::vector<std::pair<std::string, double>> last_profile() const override {
    auto p = net_->last_profile();
    if (!p.empty()) p.emplace_back("rest correctives", ms_);
    return p;
  }

 private:
  std::unique_ptr<SrInference> net_;
  RestCorrection correction_;
  double ms_ = 0;
};

}  // namespace

std::unique_ptr<SrInference> add_rest_correctives(std::unique_ptr<SrInference> net, const SrModel& model) {
  if (model.rest_correctives.empty()) return net;
  return std::make_unique<RestCorrected>(std::move(net), model);
}

}  // namespace facesr
