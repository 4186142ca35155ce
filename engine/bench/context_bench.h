#pragma once
// `facesr bench contexts`: what several characters on one rig and model cost
// (a crowd of one face, or split screen): creating the first context, which
// compiles the rig and model (RuntimeModel), against each later one, which
// shares it; and stepping all of them every frame.
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/runtime_context.h"

namespace facesr {

struct ContextBenchOptions {
  int contexts = 4;  // characters, each its own context
  int frames = 30;   // timed frames, after `warmup` untimed ones
  int warmup = 3;
  RuntimeOptions runtime;
  bool progress = true;
};

// JSON keys: first_context_ms and first_context_mb (compile + context),
// compile_ms, later_context_ms / later_context_mb (mean over the later
// contexts), later_over_first_time / later_over_first_memory (ratios),
// uncompiled_context_ms (a context made without the shared RuntimeModel, as
// before it existed), then all_step_ms / all_step_p95_ms (every context
// stepped once per frame, pipelined across contexts), sequential_step_ms
// (one after another, synchronously) and per_context_step_ms.
// Memory is resident-set growth, MB.
nlohmann::json bench_contexts(std::shared_ptr<const Rig> rig, std::shared_ptr<const SrModel> model,
                              const std::vector<std::vector<float>>& weights, const ContextBenchOptions& opt);

std::string context_bench_markdown(const nlohmann::json& r);

}  // namespace facesr
