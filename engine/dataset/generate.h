#pragma once
// The paired LR/HR dataset (paper §5): every performance is simulated frame by
// frame on the LR lattice (no collisions, the runtime's simulator) and on the
// HR mesh (the offline reference, with Embree collisions) under the same
// controls, and written as one .fsd file per performance plus manifest.json.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "perf/livelink_csv.h"
#include "rig/rig.h"
#include "sim/simulator.h"

namespace facesr {

struct DatasetOptions {
  std::vector<std::string> builtins;  // built-in performance names
  std::vector<std::string> files;     // performance files (.json keyframes or Live Link .csv)
  LiveLinkOptions csv;                // how .csv files load; their repairs' warnings go to stderr
  // Performances in the test split (the paper trains on amazement and pain
  // and tests on anger and fear); the others are training data.
  std::vector<std::string> test_names{"anger", "fear"};
  int max_frames = 0;     // > 0: only the first frames of each performance
  bool restart = false;   // discard finished and partial sequences instead of resuming
  bool collisions = true;
  bool lr_cpu = false;    // LR on the CPU reference instead of OpenCL
  std::string device;     // OpenCL device selector for LR
  bool progress = true;
  SolverOptions lr_solver, hr_solver;
};

struct DatasetSummary {
  int frames = 0, sequences = 0, resumed_frames = 0, skipped_sequences = 0;
  double hr_mean_step_s = 0, lr_mean_step_ms = 0, hr_over_lr_time = 0;
  double embedded_error_mean_cm = 0, embedded_error_max_cm = 0;
  double max_penetration_cm = 0;
  int nan_frames = 0;
  // Frames whose LR or HR solve diverged past recovery (held at the last
  // good state), and HR frames that stopped at the Newton cap above the
  // tolerance (diverged ones included). Both are kept in the .fsd with their
  // residuals; training leaves HR frames above the tolerance out (see
  // load_dataset_split).
  int diverged_frames = 0, hr_capped_frames = 0;
  double wall_s = 0;
  std::string lr_device, hr_device;
  nlohmann::json to_json() const;
};

// Writes <out_dir>/<performance>.fsd and <out_dir>/manifest.json. Resumable:
// finished sequences are kept, an interrupted one continues from its last
// complete frame (the simulators' state is saved beside it after every frame).
DatasetSummary generate_dataset(const Rig& rig, const std::string& rig_path, const std::string& out_dir,
                                const DatasetOptions& opt);

}  // namespace facesr
