#include "sr/rest_tangents.h"

#include <cmath>
#include <set>

#include <Eigen/Dense>

#include "core/error.h"

namespace facesr {

nlohmann::json rest_tangents_to_json(const RestTangents& t) {
  return {{"shapes", t.shapes}, {"amplitudes", t.amplitudes}, {"fade", t.fade}, {"ridge", t.ridge}};
}

void rest_tangents_from_json(const nlohmann::json& j, RestTangents& t, const std::string& source) {
  const std::string at = source + ": rest_tangents: ";
  require(j.is_object(), at + "not a JSON object");
  try {
    t.shapes = j.at("shapes").get<std::vector<std::string>>();
    t.amplitudes = j.at("amplitudes").get<std::vector<float>>();
    t.fade = j.at("fade").get<double>();
    t.ridge = j.at("ridge").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(at + "missing or mistyped field (" + e.what() + ")");
  }
}

void validate_rest_tangents(const RestTangents& t, int N, int M, const std::string& ctx) {
  const std::string at = ctx + ": rest tangents: ";
  const size_t S = t.shapes.size();
  require(S > 0, at + "no shapes");
  require(t.amplitudes.size() == S, at + std::to_string(t.amplitudes.size()) + " amplitudes for " +
                                        std::to_string(S) + " shapes");
  require(t.lr.size() == S * 3 * size_t(N), at + "the LR directions have " + std::to_string(t.lr.size()) +
                                                 " values, expected " + std::to_string(S * 3 * size_t(N)));
  require(t.hr.size() == S * 3 * size_t(M), at + "the HR residuals have " + std::to_string(t.hr.size()) +
                                                 " values, expected " + std::to_string(S * 3 * size_t(M)));
  require(std::isfinite(t.fade) && t.fade > 0, at + "fade must be a positive weight");
  require(std::isfinite(t.ridge) && t.ridge > 0, at + "ridge must be positive");
  std::set<std::string> seen;
  for (size_t s = 0; s < S; ++s) {
    require(!t.shapes[s].empty() && seen.insert(t.shapes[s]).second,
            at + "shape name '" + t.shapes[s] + "' is empty or repeated");
    require(std::isfinite(t.amplitudes[s]) && t.amplitudes[s] > 0,
            at + "amplitude of '" + t.shapes[s] + "' must be a positive weight");
  }
  for (float v : t.lr) require(std::isfinite(v), at + "an LR direction value is not finite");
  for (float v : t.hr) require(std::isfinite(v), at + "an HR residual value is not finite");
}

RestTangentCorrection::RestTangentCorrection(const RestTangents& t, int N, int M)
    : S_(t.count()), N3_(3 * N), M3_(3 * M), fade_(t.fade) {
  validate_rest_tangents(t, N, M, "rest-tangent correction");
  using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Mat D = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                    t.lr.data(), S_, N3_)
                    .cast<double>();  // S × 3N: the directions as rows
  Eigen::MatrixXd G = D * D.transpose();
  // Relative ridge: shapes the LR lattice barely sees (nearly parallel
  // directions) get small coefficients instead of amplified noise.
  const double lambda = t.ridge * G.diagonal().mean();
  G.diagonal().array() += lambda;
  solve_ = G.ldlt().solve(D).cast<float>();
  hr_ = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(t.hr.data(), S_, M3_);
}

std::vector<double> RestTangentCorrection::coefficients(const float* x) const {
  const Eigen::VectorXf c = solve_ * Eigen::Map<const Eigen::VectorXf>(x, N3_);
  return std::vector<double>(c.data(), c.data() + c.size());
}

double RestTangentCorrection::fade_factor(double rho) const {
  // Quartic, not Gaussian: flat near rest, so a tangent measured at weight
  // w_s is not scaled down at smaller weights (a Gaussian with fade ≈ 2.5 w_s
  // would change the slope by 15 % between 0 and w_s).
  const double u = (rho / fade_) * (rho / fade_);
  return std::exp(-u * u);
}

void RestTangentCorrection::apply(const float* x, float* y) const {
  // Float matrix-vector products (Eigen vectorises them): per frame 3N·S
  // and, near rest only, 3M·S multiply-adds, about 2 M on the ICT head.
  const Eigen::VectorXf c = solve_ * Eigen::Map<const Eigen::VectorXf>(x, N3_);
  const double phi = fade_factor(double(c.norm()));
  if (phi < 1e-12) return;
  Eigen::Map<Eigen::VectorXf>(y, M3_).noalias() += hr_.transpose() * (float(phi) * c);
}

}  // namespace facesr
