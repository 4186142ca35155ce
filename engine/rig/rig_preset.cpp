#include "rig/rig_preset.h"

#include "core/error.h"

namespace facesr {

void apply_rig_preset(RigBuildOptions& o, const std::string& preset) {
  if (preset == "default") return;
  require(preset == "coarse", "unknown rig preset '" + preset + "' (expected default or coarse)");
  o.procedural.grid_h = 0.25;
  o.procedural.edge = 0.8;
  o.flesh_grid_h = 0.3;
  o.bone_edge = 0.8;
  o.hr_max_volume = 0.15;
  o.lr_cell = 1.2;
  o.min_hr_over_lr = 0;
}

}  // namespace facesr
