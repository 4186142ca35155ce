#include "train/sr_loss.h"

#include <cmath>

namespace facesr {

torch::Tensor triangle_normals(const torch::Tensor& x, const torch::Tensor& tris) {
  const auto v0 = x.index_select(1, tris.select(1, 0));
  const auto v1 = x.index_select(1, tris.select(1, 1));
  const auto v2 = x.index_select(1, tris.select(1, 2));
  return torch::cross(v1 - v0, v2 - v0, 2);
}

LossTerms sr_loss(const torch::Tensor& pred, const torch::Tensor& target, const torch::Tensor& rest,
                  const torch::Tensor& tris, const std::vector<torch::Tensor>& features, double alpha, double beta,
                  const torch::Tensor& frame_weights) {
  const int64_t B = pred.size(0), M = pred.size(1);
  LossTerms t;
  if (frame_weights.defined())
    t.recon = ((pred - target).abs().sum({1, 2}) * frame_weights.to(pred.options())).sum() / double(B);
  else
    t.recon = (pred - target).abs().sum() / double(B);
  const auto r = rest.unsqueeze(0);
  const auto np = triangle_normals(r + pred, tris), nt = triangle_normals(r + target, tris);
  // eps keeps degenerate (zero-area) triangles from producing NaN.
  const auto cos = torch::cosine_similarity(np, nt, 2, 1e-12);
  t.normal = (1 - cos).sum() / double(B);
  t.reg = torch::zeros({}, pred.options());
  for (const auto& f : features) t.reg = t.reg + f.norm(2, 2).sum() / double(B);
  t.total = (t.recon + alpha * t.normal + beta * t.reg) / double(M);
  return t;
}

torch::Tensor relative_frame_weights(const torch::Tensor& hr, const torch::Tensor& embedded, double floor_cm) {
  const auto e = (hr - embedded).norm(2, 2).mean(1).to(torch::kFloat64);
  const auto w = 1.0 / (e + floor_cm);
  return (w / w.mean()).to(hr.scalar_type());
}

double beta_schedule(int epoch, int epochs, double beta_start, double beta_end) {
  if (epochs <= 1 || beta_start <= 0 || beta_end <= 0) return beta_end;
  const double s = double(std::min(epoch, epochs - 1)) / double(epochs - 1);
  return beta_start * std::pow(beta_end / beta_start, s);
}

}  // namespace facesr
