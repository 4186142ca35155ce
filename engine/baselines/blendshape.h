#pragma once
// The linear blendshape model, the surface a game without simulation shows:
// neutral + Σ_i w_i δ_i at the frame's ARKit weights, over the rig's face
// surface in its rest frame (the thesis's baseline; not in the paper's tables).
#include <string>
#include <vector>

#include "rig/rig.h"

namespace facesr {

class BlendshapeBaseline {
 public:
  // weight_names: the order of the weights apply() gets (a dataset's
  // manifest). A name the rig lacks is an Error; rig shapes not named stay 0.
  BlendshapeBaseline(const Rig& rig, const std::vector<std::string>& weight_names);
  // hr_disp (M × 3, cm) = Σ_i w_i δ_i; weights.size() must match the names.
  void apply(const std::vector<float>& weights, float* hr_disp) const;
  int num_surface() const { return M_; }

 private:
  int M_ = 0;
  std::vector<int> shape_of_weight_;  // rig shape per named weight
  std::vector<float> deltas_;  // the rig's, [shape][vertex][3] (a copy: the baseline may outlive the rig)
};

}  // namespace facesr
