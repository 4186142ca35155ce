#include "baselines/mls.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "baselines/frame_check.h"
#include "core/error.h"

namespace facesr {

struct MlsBaseline::Impl {
  int N = 0, M = 0, k = 0;
  double sigma = 0;
  std::vector<int32_t> index;   // M × k
  std::vector<float> weight;    // M × 3 × k
  std::vector<uint8_t> degree;  // M × 3
};

namespace {

// Weights a with c0 = Σ a_s f_s for the weighted least-squares fit of f by
// a polynomial of degree `deg` in τ; false when the normal matrix is too
// ill-conditioned to trust.
template <int n>
bool c0_weights(const std::vector<double>& w, const std::vector<double>& tau, std::vector<double>& a) {
  using Mat = Eigen::Matrix<double, n, n>;
  using Vec = Eigen::Matrix<double, n, 1>;
  const auto basis = [](double t) {
    Vec b;
    double p = 1;
    for (int r = 0; r < n; ++r, p *= t) b[r] = p;
    return b;
  };
  Mat A = Mat::Zero();
  for (size_t s = 0; s < w.size(); ++s) {
    const Vec b = basis(tau[s]);
    A.noalias() += w[s] * b * b.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Mat> eig(A);
  const Vec lam = eig.eigenvalues();  // ascending
  if (!(lam[0] > 0 && lam[0] >= MlsBaseline::kMinRcond * lam[n - 1])) return false;
  // y = A⁻¹ e0, so c0 = e0ᵀ A⁻¹ Σ w_s b_s f_s = Σ (w_s yᵀ b_s) f_s.
  const Mat& V = eig.eigenvectors();
  const Vec y = V * (V.row(0).transpose().array() / lam.array()).matrix();
  for (size_t s = 0; s < w.size(); ++s) a[s] = w[s] * y.dot(basis(tau[s]));
  return true;
}

}  // namespace

MlsBaseline::MlsBaseline(const SrGeometry& g, double sigma_cm) : impl_(std::make_unique<Impl>()) {
  validate_sr_geometry(g, "MLS baseline");
  require(std::isfinite(sigma_cm) && sigma_cm > 0, "MLS baseline: sigma = " + std::to_string(sigma_cm) +
                                                        " cm, expected a finite value > 0");
  Impl& m = *impl_;
  const int M = g.num_hr, k = g.upsample_k;
  m.N = g.num_lr;
  m.M = M;
  m.k = k;
  m.sigma = sigma_cm;
  m.index = g.up_index;
  m.weight.assign(size_t(M) * 3 * size_t(k), 0.f);
  m.degree.assign(size_t(M) * 3, 0);
  const std::vector<float>& ref = g.hr_rest_lr_frame.empty() ? g.hr_rest : g.hr_rest_lr_frame;
  const double inv_s2 = 1.0 / (sigma_cm * sigma_cm);

#pragma omp parallel
  {
    const size_t uk = static_cast<size_t>(k);
    std::vector<double> w(uk), tau(uk), a(uk);
#pragma omp for schedule(static)
    for (int j = 0; j < M; ++j) {
      const size_t row = size_t(j) * size_t(k);
      double dmin2 = 1e300;
      for (int s = 0; s < k; ++s) {
        const double d = g.up_dist[row + size_t(s)];
        dmin2 = std::min(dmin2, d * d);
      }
      for (int s = 0; s < k; ++s) {
        const double d = g.up_dist[row + size_t(s)];
        w[size_t(s)] = std::exp(-(d * d - dmin2) * inv_s2);
      }
      for (int c = 0; c < 3; ++c) {
        double h = 0;
        for (int s = 0; s < k; ++s) {
          const int node = g.up_index[row + size_t(s)];
          tau[size_t(s)] = double(g.lr_rest[size_t(node) * 3 + size_t(c)]) - double(ref[size_t(j) * 3 + size_t(c)]);
          h = std::max(h, std::abs(tau[size_t(s)]));
        }
        // Scaling t by h changes no c0 but makes the conditioning test
        // independent of units and neighbourhood size.
        if (h > 0)
          for (double& t : tau) t /= h;
        int deg = 0;
        if (h > 0 && c0_weights<3>(w, tau, a))
          deg = 2;
        else if (h > 0 && c0_weights<2>(w, tau, a))
          deg = 1;
        else
          c0_weights<1>(w, tau, a);  // Σ w > 0 (the nearest weighs 1), never refused
        m.degree[size_t(j) * 3 + size_t(c)] = uint8_t(deg);
        float* out = &m.weight[(size_t(j) * 3 + size_t(c)) * size_t(k)];
        for (int s = 0; s < k; ++s) out[s] = float(a[size_t(s)]);
      }
    }
  }
}

MlsBaseline::~MlsBaseline() = default;
MlsBaseline::MlsBaseline(MlsBaseline&&) noexcept = default;
MlsBaseline& MlsBaseline::operator=(MlsBaseline&&) noexcept = default;

void MlsBaseline::apply(const float* lr_disp, float* hr_disp) const {
  const Impl& m = *impl_;
  require_finite_frame(lr_disp, m.N, "MLS baseline");
  require(hr_disp != nullptr, "MLS baseline: null output array");
  const size_t k = size_t(m.k);
#pragma omp parallel for schedule(static)
  for (int j = 0; j < m.M; ++j) {
    const int32_t* idx = &m.index[size_t(j) * k];
    for (int c = 0; c < 3; ++c) {
      const float* a = &m.weight[(size_t(j) * 3 + size_t(c)) * k];
      double v = 0;
      for (size_t s = 0; s < k; ++s) v += double(a[s]) * double(lr_disp[size_t(idx[s]) * 3 + size_t(c)]);
      hr_disp[size_t(j) * 3 + size_t(c)] = float(v);
    }
  }
}

std::vector<float> MlsBaseline::apply(const std::vector<float>& lr_disp) const {
  require_frame_size(lr_disp, impl_->N, "MLS baseline");
  std::vector<float> out(size_t(impl_->M) * 3);
  apply(lr_disp.data(), out.data());
  return out;
}

double MlsBaseline::sigma_cm() const { return impl_->sigma; }
const std::vector<uint8_t>& MlsBaseline::degree() const { return impl_->degree; }
const std::vector<float>& MlsBaseline::weights() const { return impl_->weight; }

}  // namespace facesr
