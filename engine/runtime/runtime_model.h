#pragma once
// What every context on one rig and model needs and none changes, built
// once and shared read-only (MuJoCo's mjModel beside a context's mjData):
// the model-to-rig check (whose checksum serialises the whole rig), the LR
// simulation model, the inference plan (the weight network over every
// upsampling pair) and the rest surface. A RuntimeContext made from it holds
// only its own state: controls, solver state, device buffers, results.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "rig/rig.h"
#include "runtime/sr_inference.h"
#include "sim/sim_model.h"
#include "sr/sr_model.h"

namespace facesr {

struct RuntimeModel {
  std::shared_ptr<const Rig> rig;
  std::shared_ptr<const SrModel> model;
  uint64_t rig_checksum = 0;
  SimModel lr_model;
  SharedInferencePlan plan;
  std::vector<float> hr_rest;  // M × 3, cm: the rig's rest surface
};

// Throws Error when the model was trained on another rig or is not a
// network ("sr"). `rig_checksum`: the rig's, when the caller has it already
// (computed here otherwise). Safe to call from several threads.
std::shared_ptr<const RuntimeModel> compile_runtime_model(std::shared_ptr<const Rig> rig,
                                                          std::shared_ptr<const SrModel> model,
                                                          std::optional<uint64_t> rig_checksum = std::nullopt);

}  // namespace facesr
