#include "train/edge_conv.h"

#include <limits>

namespace facesr {

namespace F = torch::nn::functional;

EdgeConvBlockImpl::EdgeConvBlockImpl(int64_t in, int64_t out, double leaky_slope) : in_(in), slope_(leaky_slope) {
  edge_ = register_module("edge", torch::nn::Linear(2 * in, out));
  fc_ = register_module("fc", torch::nn::Linear(3 * out + in, out));
}

torch::Tensor EdgeConvBlockImpl::edge(const torch::Tensor& h, const torch::Tensor& nbr) {
  // Θ [h_i, h_j − h_i] = (Θ1 − Θ2) h_i + Θ2 h_j: two node-wise products and a
  // gather instead of a product per edge (k times fewer multiplies).
  const auto W = edge_->weight;  // out × 2in
  const auto W1 = W.narrow(1, 0, in_), W2 = W.narrow(1, in_, in_);
  const auto self = torch::matmul(h, (W1 - W2).t()) + edge_->bias;  // B × N × out
  const auto other = torch::matmul(h, W2.t());                       // B × N × out
  const int64_t B = h.size(0), N = h.size(1), k = nbr.size(2), D = other.size(2);
  const auto flat = nbr.reshape({B, N * k, 1}).expand({B, N * k, D});
  const auto gathered = torch::gather(other, 1, flat).view({B, N, k, D});
  return F::leaky_relu(self.unsqueeze(2) + gathered, F::LeakyReLUFuncOptions().negative_slope(slope_))
      .amax(2);
}

torch::Tensor EdgeConvBlockImpl::forward(const torch::Tensor& h, const torch::Tensor& nbr) {
  const auto y = edge(h, nbr);
  const int64_t D = y.size(2);
  // fc([y, g_max, g_avg, h]) split by input block: the pooled features are
  // the same for every node, so their share is one product per frame, not
  // per node (the block is then a third of the work).
  const auto W = fc_->weight;  // D × (3D + in)
  const auto gmax = y.amax(1), gavg = y.mean(1);  // B × D
  const auto pooled = torch::matmul(gmax, W.narrow(1, D, D).t()) + torch::matmul(gavg, W.narrow(1, 2 * D, D).t()) +
                      fc_->bias;  // B × D
  const auto per_node = torch::matmul(y, W.narrow(1, 0, D).t()) + torch::matmul(h, W.narrow(1, 3 * D, in_).t());
  return F::leaky_relu(per_node + pooled.unsqueeze(1), F::LeakyReLUFuncOptions().negative_slope(slope_));
}

torch::Tensor feature_knn(const torch::Tensor& h, int64_t k) {
  torch::NoGradGuard no_grad;
  const auto sq = (h * h).sum(2);  // B × N
  auto d = sq.unsqueeze(2) + sq.unsqueeze(1) - 2 * torch::bmm(h, h.transpose(1, 2));
  d.diagonal(0, 1, 2).fill_(std::numeric_limits<float>::infinity());  // a node is not its own neighbour
  return std::get<1>(d.topk(k, 2, /*largest=*/false, /*sorted=*/true));
}

}  // namespace facesr
