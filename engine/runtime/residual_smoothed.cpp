#include "runtime/residual_smoothed.h"

#include <chrono>

namespace facesr {
namespace {

class ResidualSmoothed final : public SrInference {
 public:
  ResidualSmoothed(std::unique_ptr<SrInference> net, const SrModel& m)
      : net_(std::move(net)), smoother_(m.residual_smoothing, m.geometry) {}
  void infer(const float* lr_disp, float* hr_disp) override {
    net_->infer(lr_disp, hr_disp);
    const auto t0 = std::chrono::steady_clock::now();
    smoother_.apply(lr_disp, hr_disp);
    ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  std::string device() const override { return net_->device(); }
  std::vector<std::pair<std::string, double>> last_profile() const override {
    auto p = net_->last_profile();
    if (!p.empty()) p.emplace_back("residual smoothing", ms_);
    return p;
  }

 private:
  std::unique_ptr<SrInference> net_;
  ResidualSmoother smoother_;
  double ms_ = 0;
};

}  // namespace

std::unique_ptr<SrInference> smooth_residual(std::unique_ptr<SrInference> net, const SrModel& model) {
  if (model.residual_smoothing.empty()) return net;
  return std::make_unique<ResidualSmoothed>(std::move(net), model);
}

}  // namespace facesr
