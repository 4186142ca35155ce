#include "train/interpolate.h"

#include <ATen/Dispatch.h>
#include <ATen/Parallel.h>

namespace facesr {

namespace {

// W as an M × N sparse matrix, so out = W · f is one pass over the M·K weights.
torch::Tensor sparse_weights(const torch::Tensor& w, const torch::Tensor& idx, int64_t N) {
  const int64_t M = w.size(0), K = w.size(1);
  const auto rows = torch::arange(M, idx.options()).view({M, 1}).expand({M, K}).reshape({-1});
  return torch::sparse_coo_tensor(torch::stack({rows, idx.reshape({-1})}), w.reshape({-1}), {M, N});
}

// f (B × N × C) as an N × (B·C) matrix and back.
torch::Tensor as_columns(const torch::Tensor& f) { return f.permute({1, 0, 2}).reshape({f.size(1), -1}); }
torch::Tensor from_columns(const torch::Tensor& c, int64_t B) {
  return c.view({c.size(0), B, -1}).permute({1, 0, 2}).contiguous();
}

class Interpolate : public torch::autograd::Function<Interpolate> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, const torch::Tensor& w, const torch::Tensor& idx,
                               const torch::Tensor& f) {
    ctx->save_for_backward({w, idx, f});
    const auto W = sparse_weights(w, idx, f.size(1));
    return from_columns(torch::mm(W, as_columns(f)), f.size(0));
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                 torch::autograd::variable_list grads) {
    const auto saved = ctx->get_saved_variables();
    const auto &w = saved[0], &idx = saved[1], &f = saved[2];
    const auto g = grads[0].contiguous();  // B × M × C
    const int64_t B = f.size(0), K = w.size(1);
    torch::Tensor gw, gf;
    if (ctx->needs_input_grad(2)) {
      const auto Wt = sparse_weights(w, idx, f.size(1)).t();
      gf = from_columns(torch::mm(Wt, as_columns(g)), B);
    }
    if (ctx->needs_input_grad(0)) {
      // d out[b,j,:] / d w[j,q] = f[b, idx[j,q], :]; one gather per q keeps
      // memory at B × M × C.
      gw = torch::empty_like(w);
      for (int64_t q = 0; q < K; ++q)
        gw.select(1, q).copy_((g * f.index_select(1, idx.select(1, q))).sum(at::IntArrayRef{0, 2}));
    }
    return {gw, torch::Tensor(), gf};
  }
};

}  // namespace

torch::Tensor interpolate_neighbours(const torch::Tensor& w, const torch::Tensor& idx, const torch::Tensor& f) {
  return Interpolate::apply(w, idx, f);
}

}  // namespace facesr
