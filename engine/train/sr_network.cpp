#include "train/sr_network.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "sr/positional_encoding.h"
#include "sr/upsample_inputs.h"
#include "train/interpolate.h"

namespace facesr {

namespace {

torch::Tensor long_tensor(const std::vector<int32_t>& v, std::vector<int64_t> shape) {
  return torch::from_blob(const_cast<int32_t*>(v.data()), shape, torch::kInt32).to(torch::kLong).clone();
}

torch::Tensor float_tensor(const std::vector<float>& v, std::vector<int64_t> shape) {
  return torch::from_blob(const_cast<float*>(v.data()), shape, torch::kFloat32).clone();
}

}  // namespace

SrNetworkImpl::SrNetworkImpl(const SrArchitecture& arch, const SrGeometry& g)
    : arch_(arch), N_(g.num_lr), M_(g.num_hr), K_(arch.upsample_k) {
  require(arch.kind == "sr", "SrNetwork: architecture kind is '" + arch.kind + "', expected 'sr'");
  require(g.graph_k == arch.graph_k && g.upsample_k == arch.upsample_k,
          "SrNetwork: the geometry's k values differ from the architecture's");
  pe_ = register_buffer("pe", float_tensor(positional_encoding(int(N_), arch.pe_dim, g.pe_rows), {N_, arch.pe_dim}));
  graph_ = long_tensor(g.lr_graph, {N_, arch.graph_k});

  if (arch.feature_encoding) {
    int64_t in = arch.input_dim();
    for (size_t s = 0; s < arch.encoder_dims.size(); ++s) {
      blocks_.push_back(EdgeConvBlock(in, arch.encoder_dims[s], arch.leaky_slope));
      in = arch.encoder_dims[s];
    }
    // Registered under one parent so names read "encoder.<s>.edge.weight".
    auto list = register_module("encoder", torch::nn::ModuleList());
    for (auto& b : blocks_) list->push_back(b);
  }

  if (arch.coordinate_upsampling) {
    up_index_ = long_tensor(g.up_index, {M_, K_});
    const std::vector<float> u = upsample_inputs(arch, g);
    up_input_ = register_buffer("up_input", float_tensor(u, {M_, K_, 7}));
    weight_net_ = register_module("weight_net", Siren(7, arch.weight_hidden, 1, arch.omega0));
  } else {
    up_index_ = long_tensor(g.euclid_index, {M_, K_});
    // Zero logits: uniform weights at the start, as the softmax of equal values.
    free_weights_ = register_parameter("free_weights", torch::zeros({M_, K_}));
  }
  recon_ = register_module("recon", Siren(arch.encoded_dim(), arch.recon_hidden, 3, arch.omega0));
  if (arch.embedded_skip) {
    require(g.embed_nodes.size() == size_t(4 * M_) && g.embed_weights.size() == size_t(4 * M_),
            "SrNetwork: the embedded skip needs the geometry's LR embedding");
    embed_nodes_ = long_tensor(g.embed_nodes, {M_ * 4});
    embed_weights_ = register_buffer("embed_weights", float_tensor(g.embed_weights, {M_, 4}));
  }
}

torch::Tensor SrNetworkImpl::embedded(const torch::Tensor& lr_disp) {
  const int64_t B = lr_disp.size(0);
  if (embed_nodes_.device() != lr_disp.device()) embed_nodes_ = embed_nodes_.to(lr_disp.device());
  const auto g = lr_disp.index_select(1, embed_nodes_).view({B, M_, 4, 3});
  return (g * embed_weights_.view({1, M_, 4, 1})).sum(2);
}

torch::Tensor SrNetworkImpl::encode(const torch::Tensor& lr_disp, std::vector<torch::Tensor>* features) {
  const int64_t B = lr_disp.size(0);
  require(lr_disp.dim() == 3 && lr_disp.size(1) == N_ && lr_disp.size(2) == 3,
          "SrNetwork: input must be B × " + std::to_string(N_) + " × 3");
  const auto x0 = torch::cat({lr_disp / arch_.input_scale, pe_.unsqueeze(0).expand({B, N_, arch_.pe_dim})}, 2);
  if (graph_.device() != lr_disp.device()) {
    graph_ = graph_.to(lr_disp.device());
    up_index_ = up_index_.to(lr_disp.device());
  }
  std::vector<torch::Tensor> parts{x0};
  torch::Tensor h = x0;
  for (size_t s = 0; s < blocks_.size(); ++s) {
    // The first graph is the geodesic one over the LR mesh (local); later
    // ones are rebuilt in each submodule's input feature space (§3.1).
    const auto nbr = s == 0 ? graph_.unsqueeze(0).expand({B, N_, arch_.graph_k}) : feature_knn(h, arch_.graph_k);
    h = blocks_[s]->forward(h, nbr);
    parts.push_back(h);
    if (features) features->push_back(h);
  }
  return parts.size() == 1 ? x0 : torch::cat(parts, 2);
}

torch::Tensor SrNetworkImpl::upsample_weights() {
  const auto logits = arch_.coordinate_upsampling ? weight_net_->forward(up_input_).squeeze(2) : free_weights_;
  return torch::softmax(logits, 1);  // eq. 3
}

torch::Tensor SrNetworkImpl::interpolate(const torch::Tensor& w, const torch::Tensor& f) {
  return interpolate_neighbours(w, up_index_, f);
}

SrNetworkImpl::Output SrNetworkImpl::forward(const torch::Tensor& lr_disp) {
  if (arch_.zero_rest) {
    // The rest input rides along as one more frame of the batch; its output
    // is subtracted from every frame, and its features are left out of the
    // feature-norm loss.
    const int64_t B = lr_disp.size(0);
    Output all = forward_network(torch::cat({lr_disp, torch::zeros({1, N_, 3}, lr_disp.options())}, 0));
    Output out;
    out.hr_disp = all.hr_disp.narrow(0, 0, B) - all.hr_disp.narrow(0, B, 1);
    for (auto& f : all.features) out.features.push_back(f.narrow(0, 0, B));
    if (arch_.embedded_skip) out.hr_disp = out.hr_disp + embedded(lr_disp);
    return out;
  }
  Output out = forward_network(lr_disp);
  if (arch_.embedded_skip) out.hr_disp = out.hr_disp + embedded(lr_disp);
  return out;
}

SrNetworkImpl::Output SrNetworkImpl::forward_network(const torch::Tensor& lr_disp) {
  Output out;
  const auto z = encode(lr_disp, &out.features);
  // The reconstruction's first affine map is applied on the N LR nodes and
  // then interpolated; equal to interpolating z first because each HR
  // vertex's weights sum to one (softmax), and M > N with C_enc > width.
  const auto pre = interpolate(upsample_weights(), recon_->first_linear(z));
  out.hr_disp = recon_->from_first(pre) * arch_.output_scale;
  return out;
}

}  // namespace facesr
