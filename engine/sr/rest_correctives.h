#pragma once
// Not in the paper: near-rest correctives, a correction of a trained model
// for every blendshape just off rest, measured after training on frames
// where one shape s is active alone at small weights a_s1 < … < a_sK:
//   d_s  = Δx^L(a_s1) / a_s1           LR direction per unit weight (N × 3, cm)
//   R_sk = (Δx^H − f(Δx^L))(a_sk) / φ(a_sk)  what the model f misses there (M × 3, cm)
// At run time the LR input is written in those directions by ridge least
// squares, c = argmin ‖D c − Δx^L‖² + λ‖c‖² (λ = ridge · mean diag(DᵀD)),
// and the output gains
//   φ(‖c‖) · Σ_s g_s(c_s),   φ(ρ) = exp(−(ρ / fade)⁴),
// with g_s piecewise linear through (0, 0) and every (a_sk, R_sk) (the
// in-between shapes of a corrective rig), constant beyond a_sK and the
// first segment's line below 0. So the corrected model reproduces every
// frame it was measured on, interpolates between them, never extrapolates
// a residual beyond the largest weight measured, and leaves large poses
// (where φ → 0; φ is flat near 0) to the network. A network trained mostly
// on large poses answers tiny inputs poorly (it lost to the embedded
// baseline on frames returning to rest, by 1e-6 to 1e-5 cm).
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace facesr {

struct RestCorrectives {
  std::vector<std::string> shapes;             // S blendshape names
  std::vector<std::vector<float>> amplitudes;  // per shape: a_s1 < … < a_sK, the weights measured
  std::vector<float> lr;                       // S × N × 3: d_s (cm per unit weight)
  std::vector<float> hr;                       // per shape, per sample: R_sk (M × 3, cm), in that order
  double fade = 0.2;                           // ‖c‖ at which φ = 1/e (weight units)
  double ridge = 1e-3;                         // relative Tikhonov term of the solve for c
  bool empty() const { return shapes.empty(); }
  int count() const { return int(shapes.size()); }
  int samples() const;  // Σ_s K_s
};

// Header fields (shapes, amplitudes, fade, ridge); the arrays travel as binary.
nlohmann::json rest_correctives_to_json(const RestCorrectives& t);
// Fills those fields of `t`; Errors name `source` and the key.
void rest_correctives_from_json(const nlohmann::json& j, RestCorrectives& t, const std::string& source);
// Sizes against N and M, finiteness, increasing positive amplitudes, fade
// and ridge > 0, distinct names.
void validate_rest_correctives(const RestCorrectives& t, int N, int M, const std::string& context);
// φ(ρ) = exp(−(ρ / fade)⁴): quartic, so flat near rest.
double rest_fade(double rho, double fade);

// The load-time form: the S × 3N solve matrix P = (DᵀD + λI)⁻¹Dᵀ.
class RestCorrection {
 public:
  RestCorrection(const RestCorrectives& t, int N, int M);
  // c for one LR displacement (N × 3, cm).
  std::vector<double> coefficients(const float* lr_disp) const;
  // hr_disp (M × 3, cm) += φ(‖c‖) Σ_s g_s(c_s).
  void apply(const float* lr_disp, float* hr_disp) const;

 private:
  int S_, N3_, M3_;
  double fade_;
  std::vector<std::vector<float>> amplitudes_;
  std::vector<int> first_;  // row of each shape's first sample in hr_
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> solve_;  // S × 3N
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> hr_;     // Σ K_s × 3M
};

}  // namespace facesr
