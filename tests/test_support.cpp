#include "test_support.h"

#include <cstdlib>
#include <filesystem>

namespace facesr::fixtures {

RigBuildOptions coarse_rig_options() {
  RigBuildOptions o;
  o.source = "procedural";
  o.procedural.grid_h = 0.25;
  o.procedural.edge = 0.8;
  o.flesh_grid_h = 0.3;
  o.bone_edge = 0.8;
  o.hr_max_volume = 0.15;
  o.lr_cell = 1.2;
  o.min_hr_over_lr = 0;
  o.verbose = false;
  return o;
}

const Rig& procedural_rig() {
  static const Rig rig = build_rig(coarse_rig_options());
  return rig;
}

double face_size(const Rig& r) {
  return (r.surface.colwise().maxCoeff() - r.surface.colwise().minCoeff()).norm();
}

std::string ict_dir() {
  const char* env = std::getenv("FACESR_ICT_DIR");
  return env ? env : FACESR_TEST_ICT_DIR;
}

bool have_ict() { return std::filesystem::exists(ict_dir() + "/README.md") || std::filesystem::is_directory(ict_dir()); }

}  // namespace facesr::fixtures
