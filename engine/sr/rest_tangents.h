#pragma once
// Not in the paper: a first-order correction of a trained model along every
// blendshape at rest. For each shape s, measured on a training frame where s
// alone is active at a small weight w_s:
//   d_s = Δx^L / w_s            LR displacement per unit weight (N × 3, cm)
//   r_s = (Δx^H − f(Δx^L)) / (w_s φ(w_s))  what the model f misses there, per
//                               unit weight (M × 3, cm)
// At run time the LR input is expressed in those directions by ridge least
// squares, c = argmin ‖D c − Δx^L‖² + λ‖c‖², and the output gains
//   φ(‖c‖) · Σ_s c_s r_s,   φ(ρ) = exp(−(ρ / fade)⁴).
// The corrected model reproduces each frame it was measured on, and near
// rest (φ = 1 − O(‖c‖⁴), flat) it follows the HR simulation's response to
// every shape to first order where both responses are smooth, which a network
// trained on large poses does not (it loses to the embedded baseline on
// frames returning to rest, by amounts of 1e-5 cm); the fade leaves large
// poses to the network alone.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace facesr {

struct RestTangents {
  std::vector<std::string> shapes;  // S blendshape names
  std::vector<float> amplitudes;    // S: the weight w_s each tangent was measured at
  std::vector<float> lr;            // S × N × 3: d_s (cm per unit weight)
  std::vector<float> hr;            // S × M × 3: r_s (cm per unit weight; fitted with this fade)
  double fade = 0.05;               // in weight units (‖c‖ at which φ = 1/e)
  double ridge = 1e-3;              // λ relative to the mean of diag(DᵀD)
  bool empty() const { return shapes.empty(); }
  int count() const { return int(shapes.size()); }
};

// Header fields (shapes, amplitudes, fade, ridge); the arrays travel as binary.
nlohmann::json rest_tangents_to_json(const RestTangents& t);
// Fills those fields of `t`; Errors name `source` and the key.
void rest_tangents_from_json(const nlohmann::json& j, RestTangents& t, const std::string& source);
// Sizes against N and M, finiteness, fade and ridge > 0, distinct names.
void validate_rest_tangents(const RestTangents& t, int N, int M, const std::string& context);

// The load-time form: the S × 3N solve matrix P = (DᵀD + λI)⁻¹Dᵀ.
class RestTangentCorrection {
 public:
  RestTangentCorrection(const RestTangents& t, int N, int M);
  // c for one LR displacement (N × 3, cm).
  std::vector<double> coefficients(const float* lr_disp) const;
  // hr_disp (M × 3, cm) += φ(‖c‖) Σ_s c_s r_s.
  void apply(const float* lr_disp, float* hr_disp) const;
  // φ(ρ) for this correction's fade.
  double fade_factor(double rho) const;

 private:
  int S_, N3_, M3_;
  double fade_;
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> solve_;  // S × 3N
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> hr_;     // S × 3M: r_s
};

}  // namespace facesr
