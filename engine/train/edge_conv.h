#pragma once
// One feature-encoding submodule of the paper (§3.1, fig. 2): an EdgeConv
// layer (Wang et al. 2019, DGCNN) over a k-NN graph, max and average pooling
// over all nodes for a global feature, and a shared fully connected layer on
// [edge feature, global max, global average, submodule input].
#include <torch/torch.h>

namespace facesr {

class EdgeConvBlockImpl : public torch::nn::Module {
 public:
  EdgeConvBlockImpl(int64_t in, int64_t out, double leaky_slope);

  // h: B × N × in; neighbours: B × N × k node indices (long). Returns B × N × out.
  torch::Tensor forward(const torch::Tensor& h, const torch::Tensor& neighbours);
  // The EdgeConv part alone: max over j of LeakyReLU(Θ [h_i, h_j − h_i] + b).
  torch::Tensor edge(const torch::Tensor& h, const torch::Tensor& neighbours);

 private:
  torch::nn::Linear edge_{nullptr}, fc_{nullptr};
  int64_t in_;
  double slope_;
};
TORCH_MODULE(EdgeConvBlock);

// Per node the k nearest other nodes in feature space (squared Euclidean
// distance of the rows of h, B × N × D), nearest first: B × N × k long. Not
// differentiable (indices); gradients flow through the gathered features.
torch::Tensor feature_knn(const torch::Tensor& h, int64_t k);

}  // namespace facesr
