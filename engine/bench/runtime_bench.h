#pragma once
// `facesr bench runtime`: what a game gets per frame from the runtime (LR
// simulation + super-resolution), synchronous and pipelined, against the
// cost of the HR reference simulation it replaces.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/runtime_context.h"

namespace facesr {

struct RuntimeBenchOptions {
  int frames = 60;  // timed frames per mode, after `warmup` untimed ones
  int warmup = 5;
  RuntimeOptions runtime;
  double hr_step_ms = -1;  // the HR reference's ms per frame (from a dataset or a fresh run); < 0: unknown
  std::string hr_source;   // where hr_step_ms comes from
  bool progress = true;
};

// Plays `weights` (per frame, rig order) through a RuntimeContext. JSON keys:
// lr_step_ms, sr_ms, end_to_end_ms, end_to_end_fps, pipelined_fps (the
// better of pipelined_shared_fps, both stages on the whole device, and
// pipelined_split_fps, half of it each: RuntimeOptions::split_device),
// hr_step_ms, speedup_vs_hr, plus p95s, the inference's per-stage profile,
// the device and the sizes.
nlohmann::json bench_runtime(std::shared_ptr<const Rig> rig, std::shared_ptr<const SrModel> model,
                             const std::vector<std::vector<float>>& weights, const RuntimeBenchOptions& opt);

std::string runtime_bench_markdown(const nlohmann::json& r);

}  // namespace facesr
