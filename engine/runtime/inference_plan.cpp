#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "runtime/sr_inference.h"
#include "sr/positional_encoding.h"
#include "sr/upsample_inputs.h"

namespace facesr {

SrInferencePlan make_inference_plan(const SrModel& m) {
  require(m.arch.kind == "sr", "inference: the model is a '" + m.arch.kind + "' model, not the network");
  const SrArchitecture& a = m.arch;
  SrInferencePlan p;
  p.N = m.num_lr;
  p.M = m.num_hr;
  p.K = a.upsample_k;
  p.pe = positional_encoding(p.N, a.pe_dim, m.geometry.pe_rows);
  const size_t MK = size_t(p.M) * size_t(p.K);
  std::vector<double> logits(MK);
  if (a.coordinate_upsampling) {
    p.up_index = m.geometry.up_index;
    // The weight SIREN over rest-pose inputs, in double, once at load time.
    const std::vector<float> u = upsample_inputs(a, m.geometry);
    const int layers = int(a.weight_hidden.size()) + 1;
    std::vector<double> h, next;
    for (size_t r = 0; r < MK; ++r) {
      h.assign(u.begin() + long(7 * r), u.begin() + long(7 * r + 7));
      for (int l = 0; l < layers; ++l) {
        const SrTensor& W = m.tensor("weight_net." + std::to_string(l) + ".weight");
        const SrTensor& b = m.tensor("weight_net." + std::to_string(l) + ".bias");
        const int64_t out = W.shape[0], in = W.shape[1];
        next.assign(size_t(out), 0);
        for (int64_t o = 0; o < out; ++o) {
          double s = b.values[size_t(o)];
          for (int64_t i = 0; i < in; ++i) s += double(W.values[size_t(o * in + i)]) * h[size_t(i)];
          next[size_t(o)] = s;
        }
        h.swap(next);
        if (l + 1 < layers)
          for (double& v : h) v = std::sin(a.omega0 * v);
      }
      logits[r] = h[0];
    }
  } else {
    p.up_index = m.geometry.euclid_index;
    const SrTensor& f = m.tensor("free_weights");
    for (size_t r = 0; r < MK; ++r) logits[r] = f.values[r];
  }
  p.up_weight.resize(MK);
  for (size_t j = 0; j < size_t(p.M); ++j) {
    const double* l = &logits[j * size_t(p.K)];
    const double mx = *std::max_element(l, l + p.K);
    double sum = 0;
    for (int q = 0; q < p.K; ++q) sum += std::exp(l[q] - mx);
    for (int q = 0; q < p.K; ++q) p.up_weight[j * size_t(p.K) + size_t(q)] = float(std::exp(l[q] - mx) / sum);
  }
  return p;
}

}  // namespace facesr
