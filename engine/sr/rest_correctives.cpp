#include "sr/rest_correctives.h"

#include <cmath>
#include <set>

#include <Eigen/Dense>

#include "core/error.h"

namespace facesr {

int RestCorrectives::samples() const {
  int n = 0;
  for (const auto& a : amplitudes) n += int(a.size());
  return n;
}

nlohmann::json rest_correctives_to_json(const RestCorrectives& t) {
  return {{"shapes", t.shapes}, {"amplitudes", t.amplitudes}, {"fade", t.fade}, {"ridge", t.ridge}};
}

void rest_correctives_from_json(const nlohmann::json& j, RestCorrectives& t, const std::string& source) {
  const std::string at = source + ": rest_correctives: ";
  require(j.is_object(), at + "not a JSON object");
  try {
    t.shapes = j.at("shapes").get<std::vector<std::string>>();
    t.amplitudes = j.at("amplitudes").get<std::vector<std::vector<float>>>();
    t.fade = j.at("fade").get<double>();
    t.ridge = j.at("ridge").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(at + "missing or mistyped field (" + e.what() + ")");
  }
}

void validate_rest_correctives(const RestCorrectives& t, int N, int M, const std::string& ctx) {
  const std::string at = ctx + ": rest correctives: ";
  const size_t S = t.shapes.size();
  require(S > 0, at + "no shapes");
  require(t.amplitudes.size() == S,
          at + std::to_string(t.amplitudes.size()) + " amplitude lists for " + std::to_string(S) + " shapes");
  require(std::isfinite(t.fade) && t.fade > 0, at + "fade must be a positive weight");
  require(std::isfinite(t.ridge) && t.ridge > 0, at + "ridge must be positive");
  std::set<std::string> seen;
  for (size_t s = 0; s < S; ++s) {
    require(!t.shapes[s].empty() && seen.insert(t.shapes[s]).second,
            at + "shape name '" + t.shapes[s] + "' is empty or repeated");
    const auto& a = t.amplitudes[s];
    require(!a.empty(), at + "'" + t.shapes[s] + "' has no samples");
    for (size_t k = 0; k < a.size(); ++k)
      require(std::isfinite(a[k]) && a[k] > 0 && (k == 0 || a[k] > a[k - 1]),
              at + "the amplitudes of '" + t.shapes[s] + "' must be positive and increasing");
  }
  const size_t K = size_t(t.samples());
  require(t.lr.size() == S * 3 * size_t(N), at + "the LR directions have " + std::to_string(t.lr.size()) +
                                                 " values, expected " + std::to_string(S * 3 * size_t(N)));
  require(t.hr.size() == K * 3 * size_t(M), at + "the HR residuals have " + std::to_string(t.hr.size()) +
                                                 " values, expected " + std::to_string(K * 3 * size_t(M)));
  for (float v : t.lr) require(std::isfinite(v), at + "an LR direction value is not finite");
  for (float v : t.hr) require(std::isfinite(v), at + "an HR residual value is not finite");
}

double rest_fade(double rho, double fade) {
  // Quartic, not Gaussian: flat near rest, so what was measured at small
  // weights is not scaled down there (a Gaussian with fade ≈ 2.5 a_s1
  // changes the slope by 15 % between 0 and a_s1).
  const double u = (rho / fade) * (rho / fade);
  return std::exp(-u * u);
}

RestCorrection::RestCorrection(const RestCorrectives& t, int N, int M)
    : S_(t.count()), N3_(3 * N), M3_(3 * M), fade_(t.fade), amplitudes_(t.amplitudes) {
  validate_rest_correctives(t, N, M, "rest correction");
  using RowF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::MatrixXd D = Eigen::Map<const RowF>(t.lr.data(), S_, N3_).cast<double>();  // directions as rows
  Eigen::MatrixXd G = D * D.transpose();
  // Relative ridge: shapes the LR lattice barely sees (nearly parallel
  // directions) get small coefficients instead of amplified noise.
  G.diagonal().array() += t.ridge * G.diagonal().mean();
  solve_ = G.ldlt().solve(D).cast<float>();
  hr_ = Eigen::Map<const RowF>(t.hr.data(), t.samples(), M3_);
  int row = 0;
  for (const auto& a : amplitudes_) first_.push_back(row), row += int(a.size());
}

std::vector<double> RestCorrection::coefficients(const float* x) const {
  const Eigen::VectorXf c = solve_ * Eigen::Map<const Eigen::VectorXf>(x, N3_);
  return std::vector<double>(c.data(), c.data() + c.size());
}

void RestCorrection::apply(const float* x, float* y) const {
  // Per frame 3N·S multiply-adds for c and, near rest, 3M for each of at
  // most two samples per shape.
  const Eigen::VectorXf c = solve_ * Eigen::Map<const Eigen::VectorXf>(x, N3_);
  const double phi = rest_fade(double(c.norm()), fade_);
  if (phi < 1e-12) return;
  Eigen::Map<Eigen::VectorXf> out(y, M3_);
  auto add = [&](int row, double w) {
    if (w != 0) out.noalias() += float(phi * w) * hr_.row(row).transpose();
  };
  for (int s = 0; s < S_; ++s) {
    const auto& a = amplitudes_[size_t(s)];
    const int K = int(a.size()), r0 = first_[size_t(s)];
    const double v = c[s];
    if (v <= a[0]) {
      add(r0, v / a[0]);  // the first segment, also below 0
    } else if (v >= a[K - 1]) {
      add(r0 + K - 1, 1.0);  // held, never extrapolated
    } else {
      int k = 0;
      while (v > a[size_t(k + 1)]) ++k;
      const double u = (v - a[size_t(k)]) / (a[size_t(k + 1)] - a[size_t(k)]);
      add(r0 + k, 1 - u);
      add(r0 + k + 1, u);
    }
  }
}

}  // namespace facesr
