// The network's forward pass in OpenCL (cl/sr_infer.cl). Everything that
// depends only on the model is prepared once here: the upsampling weights
// (a fixed sparse matrix), the EdgeConv weight split Θ1 − Θ2 / Θ2, the
// shared FC's per-node columns, and the output scale folded into the last
// layer. A frame uploads N × 3 floats and downloads M × 3.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "compute/cl_buffer.h"
#include "compute/cl_context.h"
#include "compute/cl_program.h"
#include "core/error.h"
#include "core/progress.h"
#include "runtime/sr_inference.h"
#include "runtime/rest_subtracted.h"
#include "runtime/residual_smoothed.h"
#include "runtime/rest_corrected.h"

namespace facesr {

namespace {

using compute::Buffer;
using compute::LocalMemory;
constexpr size_t kTile = 16;

// Columns [c0, c0 + n) of a row-major rows × cols matrix.
std::vector<float> columns(const SrTensor& t, int64_t c0, int64_t n) {
  const int64_t rows = t.shape[0], cols = t.shape[1];
  std::vector<float> out(size_t(rows * n));
  for (int64_t r = 0; r < rows; ++r)
    for (int64_t c = 0; c < n; ++c) out[size_t(r * n + c)] = t.values[size_t(r * cols + c0 + c)];
  return out;
}

uint32_t round16(uint32_t n) { return (n + 15) / 16 * 16; }

// One dense layer's weights in the layout its kernel reads: row-major
// out × K for dense_tiled (GPUs); transposed K × P, P = out rounded up to 16,
// zero-padded, for dense_simd (CPU devices), whose outputs then have row
// stride P where a next kernel reads them in 16-wide loads.
struct Dense {
  uint32_t in = 0, out = 0, P = 0;
  Buffer<float> W, b;
};

struct Block {  // one EdgeConv submodule
  uint32_t in = 0, D = 0, in_off = 0, out_off = 0;
  Dense self, other, node;  // node: per-node columns of the shared FC (its bias is per frame)
  Buffer<float> W_fc, b_fc;
};

class ClInference final : public SrInference {
 public:
  ClInference(std::shared_ptr<const SrModel> m, const ClInferenceOptions& opt, SharedInferencePlan shared)
      : m_(std::move(m)), opt_(opt), ctx_(opt.device) {
    const SrArchitecture& a = m_->arch;
    if (!shared) shared = std::make_shared<const SrInferencePlan>(make_inference_plan(*m_));
    const SrInferencePlan& plan = *shared;
    require(plan.N == m_->num_lr && plan.M == m_->num_hr, "OpenCL inference: the inference plan is another model's");
    N_ = uint32_t(plan.N);
    M_ = uint32_t(plan.M);
    K_ = uint32_t(plan.K);
    require(a.graph_k <= 16, "OpenCL inference: graph_k " + std::to_string(a.graph_k) + " is above the kernels' 16");
    require(opt.dense_width == 0 || opt.dense_width == 16 || opt.dense_width == 32,
            "OpenCL inference: dense_width " + std::to_string(opt.dense_width) + " is not 0, 16 or 32");
    require(opt.knn_list >= 1 && opt.knn_list <= 4096,
            "OpenCL inference: knn_list " + std::to_string(opt.knn_list) + " is outside 1…4096");
    prog_ = ctx_.build_program({"sr_infer.cl"}, "-cl-std=CL1.2 -DKNN_LIST=" + std::to_string(opt.knn_list));
    // Auto choices, made once: the 16-wide kernels on CPU devices.
    const bool cpu_device = ctx_.device().type != compute::DeviceType::Gpu;
    simd_ = opt.kernels == ClKernels::Auto ? cpu_device : opt.kernels == ClKernels::Simd;
    knn_ = opt.knn != ClKnn::Auto ? opt.knn : cpu_device ? ClKnn::Symmetric : ClKnn::Full;
    for (const char* k : {"sr_input", "dense_simd", "dense_simd32", "dense_tiled", "edge_max", "edge_max_simd", "pool_columns", "pool_columns_simd", "pooled_bias",
                          "row_sqnorm", "feature_knn", "feature_knn_simd", "feature_knn_pruned", "transpose_columns16",
                          "knn_bounds", "feature_knn_symmetric", "knn_select",
                          "copy_columns", "add_embedded", "upsample_features", "upsample_features_simd"})
      kernels_.emplace(k, prog_.kernel(k));
    const cl_mem_flags ro = CL_MEM_READ_ONLY;
    pe_ = Buffer<float>(ctx_, plan.pe.empty() ? std::vector<float>{0} : plan.pe, ro);
    up_w_ = Buffer<float>(ctx_, plan.up_weight, ro);
    up_idx_ = Buffer<cl_int>(ctx_, plan.up_index, ro);
    graph_ = Buffer<cl_int>(ctx_, m_->geometry.lr_graph, ro);
    if (a.embedded_skip) {
      embed_nodes_ = Buffer<cl_int>(ctx_, m_->geometry.embed_nodes, ro);
      embed_w_ = Buffer<float>(ctx_, m_->geometry.embed_weights, ro);
    }

    C_ = uint32_t(a.encoded_dim());
    uint32_t in = uint32_t(a.input_dim()), off = 0, Dmax = 1;
    if (a.feature_encoding)
      for (size_t s = 0; s < a.encoder_dims.size(); ++s) {
        const std::string p = "encoder." + std::to_string(s);
        require(in <= 256, "OpenCL inference: feature width " + std::to_string(in) + " is above the kernels' 256");
        Block b;
        b.in = in;
        b.D = uint32_t(a.encoder_dims[s]);
        b.in_off = off;
        b.out_off = off + in;
        const SrTensor& We = m_->tensor(p + ".edge.weight");
        std::vector<float> W1 = columns(We, 0, in), W2 = columns(We, in, in);
        for (size_t i = 0; i < W1.size(); ++i) W1[i] -= W2[i];
        b.self = dense_weights(W1, b.D, in, m_->tensor(p + ".edge.bias").values);
        b.other = dense_weights(W2, b.D, in, {});
        const SrTensor& Wf = m_->tensor(p + ".fc.weight");
        b.W_fc = Buffer<float>(ctx_, Wf.values, ro);
        b.b_fc = Buffer<float>(ctx_, m_->tensor(p + ".fc.bias").values, ro);
        // Per-node columns [y | h] of the shared FC; the pooled ones go into a per-frame bias.
        std::vector<float> Wy = columns(Wf, 0, b.D), Wh = columns(Wf, 3 * b.D, in), node;
        for (uint32_t r = 0; r < b.D; ++r) {
          node.insert(node.end(), Wy.begin() + r * b.D, Wy.begin() + (r + 1) * b.D);
          node.insert(node.end(), Wh.begin() + r * in, Wh.begin() + (r + 1) * in);
        }
        b.node = dense_weights(node, b.D, b.D + in, {});
        Dmax = std::max(Dmax, b.D);
        off += in;
        in = b.D;
        blocks_.push_back(std::move(b));
      }
    uint32_t width = C_, Hmax = 16;
    const int layers = int(a.recon_hidden.size()) + 1;
    for (int l = 0; l < layers; ++l) {
      const std::string p = "recon." + std::to_string(l);
      const SrTensor& W = m_->tensor(p + ".weight");
      require(uint32_t(W.shape[1]) == width, "OpenCL inference: " + p + " does not fit the previous layer");
      std::vector<float> w = W.values, b = m_->tensor(p + ".bias").values;
      if (l + 1 == layers) {
        // The output scale folded into the last affine map.
        for (float& v : w) v = float(v * a.output_scale);
        for (float& v : b) v = float(v * a.output_scale);
      }
      Dense L = dense_weights(w, uint32_t(W.shape[0]), width, b);
      Hmax = std::max(Hmax, L.P);
      width = L.out;
      recon_.push_back(std::move(L));
    }
    H0_ = recon_[0].out;
    disp_ = Buffer<float>(ctx_, 3 * N_);
    enc_ = Buffer<float>(ctx_, size_t(N_) * C_);
    self_ = Buffer<float>(ctx_, size_t(N_) * Dmax);
    other_ = Buffer<float>(ctx_, size_t(N_) * Dmax);
    y_ = Buffer<float>(ctx_, size_t(N_) * Dmax);
    pooled_ = Buffer<float>(ctx_, 2 * size_t(Dmax));
    pbias_ = Buffer<float>(ctx_, round16(Dmax));
    Np_ = (N_ + 31) / 32 * 32;  // feature_knn_simd scans 32 candidates per step
    // row_sqnorm fills the first N; the padding's +∞ keeps the k-NN scans off it.
    sq_ = Buffer<float>(ctx_, std::vector<float>(Np_, INFINITY));
    // feature_knn_symmetric: per-row bounds (the padding's −∞ records
    // nothing), candidate lists and their counts, each feature submodule's
    // last neighbours (from a full scan at the first frame), and the rows
    // to redo by a full scan.
    tau_ = Buffer<float>(ctx_, std::vector<float>(Np_, -INFINITY));
    count_ = Buffer<cl_int>(ctx_, std::vector<cl_int>(N_, 0));
    list_d_ = Buffer<float>(ctx_, size_t(N_) * size_t(opt.knn_list));
    list_j_ = Buffer<cl_int>(ctx_, size_t(N_) * size_t(opt.knn_list));
    for (size_t s = 0; s < blocks_.size(); ++s) known_.emplace_back(ctx_, size_t(N_) * size_t(a.graph_k));
    have_known_.assign(blocks_.size(), false);
    redo_count_ = Buffer<cl_int>(ctx_, 1);
    redo_ = Buffer<cl_int>(ctx_, N_);
    nbr_ = Buffer<cl_int>(ctx_, size_t(N_) * size_t(a.graph_k));
    zero_ = Buffer<float>(ctx_, std::vector<float>(round16(std::max(Dmax, Hmax)), 0.0f), ro);
    r0_ = Buffer<float>(ctx_, size_t(N_) * recon_[0].P);
    proj_ = Buffer<float>(ctx_, N_);
    order_ = Buffer<cl_int>(ctx_, N_);
    rank_ = Buffer<cl_int>(ctx_, N_);
    ha_ = Buffer<float>(ctx_, size_t(M_) * Hmax);
    hb_ = Buffer<float>(ctx_, size_t(M_) * Hmax);
    // The column reduction halves its work-group: a power of two.
    pool_local_ = 1;
    while (pool_local_ * 2 <= std::min<size_t>(256, kernels_.at("pool_columns").max_work_group_size())) pool_local_ *= 2;
  }

  std::string device() const override { return ctx_.device().device_name + " (OpenCL, float)"; }

  std::vector<std::pair<std::string, double>> last_profile() const override { return profile_; }

  void infer(const float* lr_disp, float* hr_disp) override {
    const SrArchitecture& a = m_->arch;
    profile_.clear();
    auto t0 = std::chrono::steady_clock::now();
    auto stage = [&](const char* name) {
      if (!opt_.profile) return;
      ctx_.finish();
      profile_.push_back({name, 1e3 * seconds_since(t0)});
      t0 = std::chrono::steady_clock::now();
    };
    disp_.upload(lr_disp, 3 * N_);
    k("sr_input").args(N_, uint32_t(a.pe_dim), float(1.0 / a.input_scale), disp_, pe_, enc_, C_).run_1d(N_, 64);
    stage("input");
    const float slope = float(a.leaky_slope);
    for (size_t s = 0; s < blocks_.size(); ++s) {
      const Block& b = blocks_[s];
      const uint32_t k_nn = uint32_t(a.graph_k);
      const Buffer<cl_int>* nbr = &graph_;
      if (s > 0) {
        // The graph of this submodule in its input's feature space.
        k("row_sqnorm").args(N_, b.in, enc_, C_, b.in_off, sq_).run_1d(N_, 64);
        if (knn_ == ClKnn::Pruned) {
          const float margin = project(b);
          k("feature_knn_pruned")
              .args(N_, b.in, k_nn, enc_, C_, b.in_off, sq_, proj_, order_, rank_, margin, nbr_)
              .run_1d(N_, 16);
        } else if (knn_ == ClKnn::Symmetric) {
          if (hT_.size() < size_t(Np_) * b.in) hT_ = Buffer<float>(ctx_, size_t(Np_) * b.in);
          k("transpose_columns16").args(N_, Np_, b.in, enc_, C_, b.in_off, hT_).run_1d(size_t(Np_ / 16) * b.in, 16);
          if (!have_known_[s]) {  // no bounds yet: one full scan
            k("feature_knn_simd").args(N_, Np_, b.in, k_nn, hT_, sq_, no_rows_, N_, known_[s]).run_1d((N_ + 7) / 8, 8);
            have_known_[s] = true;
          } else {
            k("knn_bounds").args(N_, b.in, k_nn, enc_, C_, b.in_off, sq_, known_[s], tau_).run_1d(N_, 64);
            k("feature_knn_symmetric")
                .args(N_, Np_, b.in, hT_, sq_, tau_, count_, list_d_, list_j_)
                .run_1d((N_ + 7) / 8, 1);
            const cl_int zero = 0;
            redo_count_.upload(&zero, 1);
            k("knn_select").args(N_, k_nn, count_, list_d_, list_j_, known_[s], redo_count_, redo_).run_1d(N_, 64);
            cl_int redo = 0;
            redo_count_.download(&redo, 1);
            if (redo > 0)
              k("feature_knn_simd")
                  .args(N_, Np_, b.in, k_nn, hT_, sq_, redo_, uint32_t(redo), known_[s])
                  .run_1d((size_t(redo) + 7) / 8, 8);
          }
        } else if (knn_ == ClKnn::Simd) {
          if (hT_.size() < size_t(Np_) * b.in) hT_ = Buffer<float>(ctx_, size_t(Np_) * b.in);
          k("transpose_columns16").args(N_, Np_, b.in, enc_, C_, b.in_off, hT_).run_1d(size_t(Np_ / 16) * b.in, 16);
          k("feature_knn_simd").args(N_, Np_, b.in, k_nn, hT_, sq_, no_rows_, N_, nbr_).run_1d((N_ + 7) / 8, 8);  // 8 queries per work-item
        } else {
          k("feature_knn").args(N_, b.in, k_nn, enc_, C_, b.in_off, sq_, nbr_).run_1d(N_, 16);
        }
        nbr = knn_ == ClKnn::Symmetric ? &known_[s] : &nbr_;
        stage("feature knn");
      }
      dense(N_, b.self, enc_, C_, b.in_off, enc_, C_, 0, b.self.b, self_, b.D, 0, kNone);
      dense(N_, b.other, enc_, C_, b.in_off, enc_, C_, 0, zero_, other_, b.D, 0, kNone);
      const bool simd_cols = simd_ && b.D % 16 == 0;
      if (simd_cols)
        k("edge_max_simd").args(N_, b.D, k_nn, self_, other_, *nbr, slope, y_).run_1d(size_t(N_) * (b.D / 16), 16);
      else
        k("edge_max").args(N_, b.D, k_nn, self_, other_, *nbr, slope, y_).run_1d(size_t(N_) * b.D, 64);
      stage("edgeconv");
      if (simd_cols)
        k("pool_columns_simd").args(N_, b.D, y_, pooled_).run_1d(b.D / 16, 1);
      else
        k("pool_columns")
            .args(N_, b.D, y_, pooled_, LocalMemory{pool_local_ * sizeof(float)},
                  LocalMemory{pool_local_ * sizeof(float)})
            .run_1d(size_t(b.D) * pool_local_, pool_local_);
      k("pooled_bias").args(b.D, b.in, b.W_fc, b.b_fc, pooled_, pbias_).run_1d(b.D, 64);
      dense(N_, b.node, y_, b.D, 0, enc_, C_, b.in_off, pbias_, enc_, C_, b.out_off, kLeaky, 0, b.in);
      stage("pool + shared fc");
    }
    // Reconstruction: the first affine map on the N LR nodes, then the fixed
    // upsampling, then the remaining SIREN layers on the M HR vertices.
    const float w0 = float(a.omega0);
    const Dense& R0 = recon_[0];
    dense(N_, R0, enc_, C_, 0, enc_, C_, 0, R0.b, r0_, R0.P, 0, kNone);
    stage("recon first layer (LR nodes)");
    if (simd_)
      k("upsample_features_simd").args(M_, K_, R0.P, up_w_, up_idx_, r0_, w0, ha_).run_1d(size_t(M_) * (R0.P / 16), 16);
    else
      k("upsample_features").args(M_, K_, H0_, up_w_, up_idx_, r0_, w0, ha_).run_1d(size_t(M_) * H0_, 64);
    stage("upsample");
    Buffer<float>*in = &ha_, *out = &hb_;
    uint32_t stride = R0.P;
    for (size_t l = 1; l < recon_.size(); ++l) {
      const Dense& L = recon_[l];
      const bool last = l + 1 == recon_.size();
      const uint32_t out_stride = last ? L.out : L.P;  // the last writes the compact M × 3 result
      dense(M_, L, *in, stride, 0, *in, stride, 0, L.b, *out, out_stride, 0, last ? kNone : kSine, w0);
      stride = out_stride;
      std::swap(in, out);
    }
    if (a.embedded_skip) k("add_embedded").args(M_, embed_nodes_, embed_w_, disp_, *in).run_1d(3 * size_t(M_), 64);
    in->download(hr_disp, 3 * size_t(M_));
    stage("recon SIREN (HR vertices) + read-back");
  }

 private:
  compute::Kernel& k(const char* name) { return kernels_.at(name); }

  // The per-frame order for feature_knn_pruned: the submodule input's
  // principal direction u (power iteration on the centred features, started
  // from last frame's u), the nodes sorted by h·u, and each node's rank.
  // Returns the rounding margin for the pruning test.
  float project(const Block& b) {
    const uint32_t D = b.in;
    if (compact_.size() < size_t(N_) * D) compact_ = Buffer<float>(ctx_, size_t(N_) * D);
    k("copy_columns").args(N_, D, enc_, C_, b.in_off, compact_).run_1d(size_t(N_) * D, 64);
    host_h_.resize(size_t(N_) * D);
    compact_.download(host_h_.data(), host_h_.size());
    std::vector<double> mean(D, 0.0), u = u_.size() == D ? u_ : std::vector<double>(D, 1.0), v(D);
    double sqmax = 0;
    for (uint32_t i = 0; i < N_; ++i) {
      double sq = 0;
      for (uint32_t c = 0; c < D; ++c) {
        const double x = host_h_[size_t(i) * D + c];
        mean[c] += x;
        sq += x * x;
      }
      sqmax = std::max(sqmax, sq);
    }
    for (double& m : mean) m /= N_;
    std::vector<double> t(N_);
    for (int it = 0; it < 8; ++it) {
      double norm = 0;
      for (double x : u) norm += x * x;
      norm = std::sqrt(norm);
      if (norm == 0) break;
      for (double& x : u) x /= norm;
      std::fill(v.begin(), v.end(), 0.0);
      for (uint32_t i = 0; i < N_; ++i) {
        const float* h = &host_h_[size_t(i) * D];
        double dot = 0;
        for (uint32_t c = 0; c < D; ++c) dot += (h[c] - mean[c]) * u[c];
        for (uint32_t c = 0; c < D; ++c) v[c] += dot * (h[c] - mean[c]);
      }
      u.swap(v);
    }
    double norm = 0;
    for (double x : u) norm += x * x;
    norm = std::sqrt(norm);
    if (!(norm > 0)) {
      u.assign(D, 0.0);
      u[0] = 1;
      norm = 1;
    }
    for (double& x : u) x /= norm;
    u_ = u;
    std::vector<int32_t> order(N_), rank(N_);
    for (uint32_t i = 0; i < N_; ++i) {
      double p = 0;
      for (uint32_t c = 0; c < D; ++c) p += host_h_[size_t(i) * D + c] * u[c];
      t[i] = p;
      order[i] = int32_t(i);
    }
    std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) { return t[a] < t[b] || (t[a] == t[b] && a < b); });
    std::vector<float> ps(N_);
    for (uint32_t r = 0; r < N_; ++r) {
      ps[r] = float(t[size_t(order[r])]);
      rank[size_t(order[r])] = int32_t(r);
    }
    proj_.upload(ps);
    order_.upload(order);
    rank_.upload(rank);
    // The distance formula's float error is below ~D·2⁻²⁴·(|a|² + |b|²);
    // 1e-5 · 2 max|h|² covers D up to about 80 with a wide safety factor.
    return float(1e-5 * 2 * sqmax * std::max(1.0, D / 64.0) + 1e-12);
  }

  enum Act : cl_int { kNone = 0, kLeaky = 1, kSine = 2 };
  // W: out × K row-major; bias: out values or empty (its bias comes per call).
  Dense dense_weights(const std::vector<float>& W, uint32_t out, uint32_t K, const std::vector<float>& bias) {
    Dense d;
    d.in = K;
    d.out = out;
    d.P = simd_ ? round16(out) : out;
    std::vector<float> w = W, b = bias;
    if (simd_) {
      w.assign(size_t(K) * d.P, 0.0f);
      for (uint32_t o = 0; o < out; ++o)
        for (uint32_t c = 0; c < K; ++c) w[size_t(c) * d.P + o] = W[size_t(o) * K + c];
      if (!b.empty()) b.resize(d.P, 0.0f);
    }
    d.W = Buffer<float>(ctx_, w, CL_MEM_READ_ONLY);
    if (!b.empty()) d.b = Buffer<float>(ctx_, b, CL_MEM_READ_ONLY);
    return d;
  }

  // out = act([a1 | a2] Wᵀ + bias): a1 gives the first L.in − K2 input columns, a2 the last K2.
  void dense(uint32_t rows, const Dense& L, const Buffer<float>& a1, uint32_t s1, uint32_t off1,
             const Buffer<float>& a2, uint32_t s2, uint32_t off2, const Buffer<float>& bias, Buffer<float>& out,
             uint32_t out_stride, uint32_t out_off, Act act, float omega0 = 0, uint32_t K2 = 0) {
    const uint32_t K1 = L.in - K2;
    const float slope = float(m_->arch.leaky_slope);
    if (simd_) {
      const uint32_t width = opt_.dense_width == 16 || L.P % 32 != 0 ? 16 : 32;
      k(width == 32 ? "dense_simd32" : "dense_simd")
          .args(rows, L.out, L.P, K1, K2, a1, s1, off1, a2, s2, off2, L.W, bias, out, out_stride, out_off,
                cl_int(act), omega0, slope)
          .run_1d(size_t((rows + 7) / 8) * (L.P / width), 8);
    } else {
      const size_t tiles = ((rows + kTile - 1) / kTile) * ((L.out + kTile - 1) / kTile);
      k("dense_tiled")
          .args(rows, L.out, K1, K2, a1, s1, off1, a2, s2, off2, L.W, bias, out, out_stride, out_off, cl_int(act),
                omega0, slope)
          .run_1d(tiles * kTile * kTile, kTile * kTile);
    }
  }

  std::shared_ptr<const SrModel> m_;
  ClInferenceOptions opt_;
  compute::Context ctx_;
  compute::Program prog_;
  std::map<std::string, compute::Kernel> kernels_;
  uint32_t N_ = 0, M_ = 0, K_ = 0, C_ = 0, H0_ = 0, Np_ = 0;
  bool simd_ = false;  // CPU device: dense_simd and the other 16-wide kernels
  ClKnn knn_ = ClKnn::Full;  // opt_.knn with Auto resolved
  std::vector<Block> blocks_;
  std::vector<Dense> recon_;
  Buffer<float> pe_, up_w_, disp_, enc_, self_, other_, y_, pooled_, pbias_, sq_, zero_, r0_, ha_, hb_;
  Buffer<cl_int> up_idx_, graph_, nbr_, order_, rank_, embed_nodes_;
  Buffer<float> embed_w_;
  Buffer<float> proj_, compact_, hT_, tau_, list_d_;
  Buffer<cl_int> count_, list_j_;
  std::vector<Buffer<cl_int>> known_;
  std::vector<bool> have_known_;
  Buffer<cl_int> redo_count_, redo_, no_rows_;  // no_rows_: empty, binds as NULL
  std::vector<float> host_h_;
  std::vector<double> u_;
  size_t pool_local_ = 64;
  std::vector<std::pair<std::string, double>> profile_;
};

}  // namespace

std::unique_ptr<SrInference> make_cl_inference(std::shared_ptr<const SrModel> model, const ClInferenceOptions& opt,
                                               SharedInferencePlan plan) {
  require(model != nullptr, "inference: no model");
  std::unique_ptr<SrInference> net = std::make_unique<ClInference>(model, opt, std::move(plan));
  return add_rest_correctives(smooth_residual(subtract_rest_output(std::move(net), *model), *model), *model);
}

}  // namespace facesr
