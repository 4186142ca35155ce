#include "baselines/blendshape.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace facesr {

BlendshapeBaseline::BlendshapeBaseline(const Rig& rig, const std::vector<std::string>& weight_names)
    : M_(int(rig.surface.rows())), deltas_(rig.blendshape_deltas) {
  const size_t B = rig.blendshape_names.size();
  require(rig.blendshape_deltas.size() == B * size_t(M_) * 3,
          "blendshape baseline: rig '" + rig.name + "' has " + std::to_string(rig.blendshape_deltas.size()) +
              " delta values, expected " + std::to_string(B * size_t(M_) * 3));
  for (const auto& n : weight_names) {
    const auto it = std::find(rig.blendshape_names.begin(), rig.blendshape_names.end(), n);
    require(it != rig.blendshape_names.end(), "blendshape baseline: rig '" + rig.name + "' has no shape '" + n + "'");
    shape_of_weight_.push_back(int(it - rig.blendshape_names.begin()));
  }
}

void BlendshapeBaseline::apply(const std::vector<float>& w, float* out) const {
  require(w.size() == shape_of_weight_.size(), "blendshape baseline: " + std::to_string(w.size()) +
                                                   " weights, expected " + std::to_string(shape_of_weight_.size()));
  std::fill(out, out + 3 * size_t(M_), 0.0f);
  for (size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0) continue;
    require(std::isfinite(w[i]), "blendshape baseline: weight " + std::to_string(i) + " is not finite");
    const float* d = deltas_.data() + size_t(shape_of_weight_[i]) * size_t(M_) * 3;
    for (size_t k = 0; k < 3 * size_t(M_); ++k) out[k] += w[i] * d[k];
  }
}

}  // namespace facesr
