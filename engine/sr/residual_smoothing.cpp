#include "sr/residual_smoothing.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace facesr {

nlohmann::json residual_smoothing_to_json(const ResidualSmoothing& s) {
  return {{"operator", "umbrella"}, {"lambda", s.lambda}, {"iterations", s.iterations}};
}

ResidualSmoothing residual_smoothing_from_json(const nlohmann::json& j, const std::string& source) {
  const std::string at = source + ": residual_smoothing: ";
  require(j.is_object(), at + "not a JSON object");
  ResidualSmoothing s;
  try {
    require(j.at("operator").get<std::string>() == "umbrella",
            at + "operator '" + j.at("operator").get<std::string>() + "' is not known (expected umbrella)");
    s.lambda = j.at("lambda").get<double>();
    s.iterations = j.at("iterations").get<int>();
  } catch (const nlohmann::json::exception& e) {
    throw Error(at + "missing or mistyped field (" + e.what() + ")");
  }
  validate_residual_smoothing(s, source);
  return s;
}

void validate_residual_smoothing(const ResidualSmoothing& s, const std::string& ctx) {
  const std::string at = ctx + ": residual smoothing: ";
  require(std::isfinite(s.lambda) && s.lambda > 0 && s.lambda <= 1,
          at + "lambda must be in (0, 1], not " + std::to_string(s.lambda));
  const std::string range = "iterations must be 0 to " + std::to_string(kMaxSmoothingIterations);
  require(s.iterations >= 0 && s.iterations <= kMaxSmoothingIterations,
          at + range + ", not " + std::to_string(s.iterations));
}

ResidualSmoother::ResidualSmoother(const ResidualSmoothing& s, const SrGeometry& g) : s_(s), M_(g.num_hr) {
  validate_residual_smoothing(s, "model");
  const size_t M = size_t(M_);
  require(g.embed_nodes.size() == 4 * M && g.embed_weights.size() == 4 * M,
          "residual smoothing needs the model's surface embedding "
          "(embed_nodes, embed_weights for " +
              std::to_string(M) + " vertices)");
  require(!g.hr_tris.empty() && g.hr_tris.size() % 3 == 0, "residual smoothing needs the model's surface triangles");
  std::vector<std::vector<int32_t>> adj(M);
  for (size_t t = 0; t < g.hr_tris.size(); t += 3)
    for (int a = 0; a < 3; ++a) {
      const int32_t i = g.hr_tris[t + a], j = g.hr_tris[t + (a + 1) % 3];
      require(i >= 0 && j >= 0 && size_t(i) < M && size_t(j) < M,
              "residual smoothing: a surface triangle's vertex is out of range");
      adj[size_t(i)].push_back(j);
      adj[size_t(j)].push_back(i);
    }
  start_.assign(M + 1, 0);
  for (size_t i = 0; i < M; ++i) {
    std::sort(adj[i].begin(), adj[i].end());
    adj[i].erase(std::unique(adj[i].begin(), adj[i].end()), adj[i].end());
    start_[i + 1] = start_[i] + int32_t(adj[i].size());
    nbr_.insert(nbr_.end(), adj[i].begin(), adj[i].end());
  }
  embed_nodes_ = g.embed_nodes;
  embed_weights_ = g.embed_weights;
  embedded_.resize(3 * M);
  r_.resize(3 * M);
  next_.resize(3 * M);
}

void ResidualSmoother::apply(const float* lr_disp, float* hr_disp) {
  if (s_.empty()) return;
  const float lambda = float(s_.lambda);
  for (int v = 0; v < M_; ++v)
    for (int d = 0; d < 3; ++d) {
      float e = 0;
      for (int a = 0; a < 4; ++a) e += embed_weights_[4 * v + a] * lr_disp[3 * size_t(embed_nodes_[4 * v + a]) + d];
      embedded_[3 * v + d] = e;
      r_[3 * v + d] = hr_disp[3 * v + d] - e;
    }
  for (int k = 0; k < s_.iterations; ++k) {
    for (int v = 0; v < M_; ++v) {
      const int32_t b = start_[v], n = start_[v + 1] - b;
      if (n == 0) {  // an isolated vertex has no neighbourhood to average
        for (int d = 0; d < 3; ++d) next_[3 * v + d] = r_[3 * v + d];
        continue;
      }
      float m[3] = {0, 0, 0};
      for (int32_t t = b; t < b + n; ++t)
        for (int d = 0; d < 3; ++d) m[d] += r_[3 * size_t(nbr_[t]) + d];
      for (int d = 0; d < 3; ++d) next_[3 * v + d] = r_[3 * v + d] + lambda * (m[d] / float(n) - r_[3 * v + d]);
    }
    r_.swap(next_);
  }
  for (size_t i = 0; i < r_.size(); ++i) hr_disp[i] = embedded_[i] + r_[i];
}

}  // namespace facesr
