// The C++ reference of the network's forward pass (float, Eigen, OpenMP),
// written as plainly as the network is described: the OpenCL kernels and
// LibTorch are checked against it and each other.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "runtime/sr_inference.h"
#include "runtime/rest_subtracted.h"
#include "runtime/residual_smoothed.h"
#include "runtime/rest_corrected.h"

namespace facesr {

namespace {

using RowMat = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using ConstMap = Eigen::Map<const RowMat>;

RowMat weight(const SrModel& m, const std::string& name) {
  const SrTensor& t = m.tensor(name);
  return ConstMap(t.values.data(), t.shape[0], t.shape[1]);
}
Eigen::RowVectorXf bias(const SrModel& m, const std::string& name) {
  const SrTensor& t = m.tensor(name);
  return Eigen::Map<const Eigen::RowVectorXf>(t.values.data(), t.shape[0]);
}
void leaky(RowMat& x, float slope) { x = x.unaryExpr([slope](float v) { return v > 0 ? v : slope * v; }); }

// The k nearest other rows of h by squared distance |a|² + |b|² − 2a·b, as
// LibTorch's feature_knn computes it, nearest first (ties by index).
std::vector<int32_t> feature_knn(const RowMat& h, int k) {
  const int64_t N = h.rows();
  const Eigen::VectorXf sq = h.rowwise().squaredNorm();
  std::vector<int32_t> out(size_t(N * k));
#pragma omp parallel for schedule(static)
  for (int64_t i = 0; i < N; ++i) {
    const Eigen::VectorXf dots = h * h.row(i).transpose();
    std::vector<std::pair<float, int32_t>> d(static_cast<size_t>(N));
    for (int64_t j = 0; j < N; ++j)
      d[size_t(j)] = {j == i ? std::numeric_limits<float>::infinity() : sq[i] + sq[j] - 2 * dots[j], int32_t(j)};
    std::partial_sort(d.begin(), d.begin() + k, d.end());
    for (int q = 0; q < k; ++q) out[size_t(i * k + q)] = d[size_t(q)].second;
  }
  return out;
}

class CpuInference final : public SrInference {
 public:
  CpuInference(std::shared_ptr<const SrModel> m, SharedInferencePlan plan)
      : m_(std::move(m)), plan_p_(plan ? std::move(plan) : std::make_shared<const SrInferencePlan>(make_inference_plan(*m_))),
        plan_(*plan_p_) {
    require(plan_.N == m_->num_lr && plan_.M == m_->num_hr, "inference: the inference plan is another model's");
  }

  std::string device() const override { return "cpu-reference (Eigen, float)"; }

  void infer(const float* lr_disp, float* hr_disp) override {
    const SrArchitecture& a = m_->arch;
    const int64_t N = plan_.N, M = plan_.M, K = plan_.K, D0 = a.input_dim();
    const float slope = float(a.leaky_slope);
    RowMat x0(N, D0);
    for (int64_t i = 0; i < N; ++i) {
      for (int c = 0; c < 3; ++c) x0(i, c) = float(lr_disp[3 * i + c] / a.input_scale);
      for (int c = 0; c < a.pe_dim; ++c) x0(i, 3 + c) = plan_.pe[size_t(i * a.pe_dim + c)];
    }
    std::vector<RowMat> parts{x0};
    RowMat h = x0;
    if (a.feature_encoding)
      for (size_t s = 0; s < a.encoder_dims.size(); ++s) {
        const std::string p = "encoder." + std::to_string(s);
        const int64_t in = h.cols(), D = a.encoder_dims[s];
        const int k = a.graph_k;
        const std::vector<int32_t> nbr = s == 0 ? m_->geometry.lr_graph : feature_knn(h, k);
        // EdgeConv: max over neighbours j of LeakyReLU(Θ [h_i, h_j − h_i] + b).
        const RowMat W = weight(*m_, p + ".edge.weight");
        const Eigen::RowVectorXf b = bias(*m_, p + ".edge.bias");
        RowMat y = RowMat::Constant(N, D, -std::numeric_limits<float>::infinity());
        for (int64_t i = 0; i < N; ++i)
          for (int q = 0; q < k; ++q) {
            const int64_t j = nbr[size_t(i * k + q)];
            Eigen::RowVectorXf e(2 * in);
            e << h.row(i), h.row(j) - h.row(i);
            Eigen::RowVectorXf v = e * W.transpose() + b;
            for (int64_t c = 0; c < D; ++c) y(i, c) = std::max(y(i, c), v[c] > 0 ? v[c] : slope * v[c]);
          }
        // Shared FC on [y, global max, global average, input].
        const Eigen::RowVectorXf gmax = y.colwise().maxCoeff(), gavg = y.colwise().mean();
        RowMat cat(N, 3 * D + in);
        cat << y, gmax.replicate(N, 1), gavg.replicate(N, 1), h;
        RowMat z = (cat * weight(*m_, p + ".fc.weight").transpose()).rowwise() + bias(*m_, p + ".fc.bias");
        leaky(z, slope);
        parts.push_back(z);
        h = z;
      }
    int64_t C = 0;
    for (const auto& part : parts) C += part.cols();
    RowMat enc(N, C);
    int64_t col = 0;
    for (const auto& part : parts) {
      enc.middleCols(col, part.cols()) = part;
      col += part.cols();
    }
    // Upsampling of the encoded features, then the reconstruction SIREN.
    RowMat zh = RowMat::Zero(M, C);
    for (int64_t j = 0; j < M; ++j)
      for (int64_t q = 0; q < K; ++q)
        zh.row(j) += plan_.up_weight[size_t(j * K + q)] * enc.row(plan_.up_index[size_t(j * K + q)]);
    const int layers = int(a.recon_hidden.size()) + 1;
    RowMat x = zh;
    for (int l = 0; l < layers; ++l) {
      const std::string p = "recon." + std::to_string(l);
      if (l > 0) x = x.unaryExpr([w = float(a.omega0)](float v) { return std::sin(w * v); });
      x = (x * weight(*m_, p + ".weight").transpose()).rowwise() + bias(*m_, p + ".bias");
    }
    for (int64_t j = 0; j < M; ++j)
      for (int c = 0; c < 3; ++c) hr_disp[3 * j + c] = float(x(j, c) * a.output_scale);
    if (a.embedded_skip) {
      const auto& nodes = m_->geometry.embed_nodes;
      const auto& w = m_->geometry.embed_weights;
      for (int64_t j = 0; j < M; ++j)
        for (int c = 0; c < 3; ++c) {
          float e = 0;
          for (int k = 0; k < 4; ++k) e += w[size_t(4 * j + k)] * lr_disp[3 * nodes[size_t(4 * j + k)] + c];
          hr_disp[3 * j + c] += e;
        }
    }
  }

 private:
  std::shared_ptr<const SrModel> m_;
  SharedInferencePlan plan_p_;
  const SrInferencePlan& plan_;
};

}  // namespace

std::unique_ptr<SrInference> make_cpu_inference(std::shared_ptr<const SrModel> model, SharedInferencePlan plan) {
  require(model != nullptr, "inference: no model");
  std::unique_ptr<SrInference> net = std::make_unique<CpuInference>(model, std::move(plan));
  return add_rest_correctives(smooth_residual(subtract_rest_output(std::move(net), *model), *model), *model);
}

}  // namespace facesr
