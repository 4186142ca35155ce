#include "train/model_export.h"

#include "core/error.h"

namespace facesr {

namespace {

torch::Tensor find_parameter(torch::nn::Module& module, const std::string& name,
                             const std::vector<int64_t>& shape) {
  auto params = module.named_parameters(true);
  const torch::Tensor* p = params.find(name);
  require(p != nullptr, "the network has no parameter '" + name + "' that its architecture names");
  require(p->sizes().vec() == shape, "the network's parameter '" + name + "' has another shape than its architecture's");
  return *p;
}

}  // namespace

void export_parameters(torch::nn::Module& module, SrModel& model) {
  const auto shapes = parameter_shapes(model.arch, model.num_lr, model.num_hr);
  require(module.named_parameters(true).size() == shapes.size(),
          "the network has " + std::to_string(module.named_parameters(true).size()) +
              " parameters, its architecture names " + std::to_string(shapes.size()));
  model.tensors.clear();
  for (const auto& [name, shape] : shapes) {
    const auto p = find_parameter(module, name, shape).detach().to(torch::kCPU, torch::kFloat32).contiguous();
    SrTensor t;
    t.name = name;
    t.shape = shape;
    t.values.assign(p.data_ptr<float>(), p.data_ptr<float>() + p.numel());
    model.tensors.push_back(std::move(t));
  }
}

void import_parameters(const SrModel& model, torch::nn::Module& module) {
  torch::NoGradGuard no_grad;
  for (const SrTensor& t : model.tensors) {
    auto p = find_parameter(module, t.name, t.shape);
    const auto src = torch::from_blob(const_cast<float*>(t.values.data()), t.shape, torch::kFloat32);
    p.copy_(src.to(p.device()));
  }
}

}  // namespace facesr
