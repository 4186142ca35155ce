#include "bench/context_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <malloc.h>
#include <unistd.h>

#include "bench/bench_stats.h"
#include "core/error.h"
#include "core/progress.h"

namespace facesr {

using nlohmann::json;

namespace {

// Resident set, MB (Linux /proc; 0 where it cannot be read).
double resident_mb() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  if (!(f >> pages >> resident)) return 0;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

using bench_stats::mean;
using bench_stats::p95;

}  // namespace

json bench_contexts(std::shared_ptr<const Rig> rig, std::shared_ptr<const SrModel> model,
                    const std::vector<std::vector<float>>& weights, const ContextBenchOptions& opt) {
  require(opt.contexts >= 2 && opt.contexts <= 64, "bench contexts: --contexts must be in [2, 64]");
  require(opt.frames > 0 && opt.warmup >= 0, "bench contexts: frames must be positive");
  require(!weights.empty(), "bench contexts: no performance frames");
  const int C = opt.contexts, total = opt.warmup + opt.frames;
  Progress progress("bench contexts", C + 1 + total, opt.progress);

  // A context made the way it was before RuntimeModel (compiling its own),
  // first, so that the process-wide start-up (OpenCL platform, kernel cache)
  // is paid by neither of the measured ones.
  double uncompiled_ms = 0;
  {
    const auto t0 = std::chrono::steady_clock::now();
    RuntimeContext c(rig, model, opt.runtime);
    uncompiled_ms = 1e3 * seconds_since(t0);
  }
  // Hand its freed pages back, so that the first measured context's memory
  // is not served from them.
  malloc_trim(0);
  progress.update(1, "uncompiled");

  std::vector<std::unique_ptr<RuntimeContext>> ctx;
  std::vector<double> ms, mb;
  double compile_ms = 0;
  std::shared_ptr<const RuntimeModel> compiled;
  for (int i = 0; i < C; ++i) {
    const double r0 = resident_mb();
    const auto t0 = std::chrono::steady_clock::now();
    if (i == 0) {
      compiled = compile_runtime_model(rig, model);
      compile_ms = 1e3 * seconds_since(t0);
    }
    ctx.push_back(std::make_unique<RuntimeContext>(compiled, opt.runtime));
    ms.push_back(1e3 * seconds_since(t0));
    mb.push_back(resident_mb() - r0);
    progress.update(2 + i, "create");
  }
  const std::vector<double> later_ms(ms.begin() + 1, ms.end()), later_mb(mb.begin() + 1, mb.end());

  // Every character steps each frame, each at its own point of the
  // performance; all are queued before any is waited for, so the contexts'
  // pipelines overlap as a game's frame would let them.
  std::vector<double> all, seq;
  int diverged = 0;
  auto frame_weights = [&](int f, int i) -> const std::vector<float>& {
    return weights[size_t(f + i * 17) % weights.size()];
  };
  for (int f = 0; f < total; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < C; ++i) {
      ctx[size_t(i)]->set_weights(frame_weights(f, i));
      ctx[size_t(i)]->step_async();
    }
    for (auto& c : ctx) {
      c->wait();
      diverged += c->result().status == StepStatus::Diverged;
    }
    if (f >= opt.warmup) all.push_back(1e3 * seconds_since(t0));
    progress.update(C + 1 + f + 1, "step all");
  }
  for (int f = 0; f < opt.frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < C; ++i) {
      ctx[size_t(i)]->set_weights(frame_weights(f, i));
      ctx[size_t(i)]->step();
      diverged += ctx[size_t(i)]->result().status == StepStatus::Diverged;
    }
    seq.push_back(1e3 * seconds_since(t0));
  }
  progress.finish();

  json r;
  r["contexts"] = C;
  r["frames"] = opt.frames;
  r["device"] = ctx[0]->device();
  r["surface_vertices"] = rig->num_surface_vertices();
  r["compile_ms"] = compile_ms;
  r["first_context_ms"] = ms[0];
  r["first_context_mb"] = mb[0];
  r["later_context_ms"] = mean(later_ms);
  r["later_context_mb"] = mean(later_mb);
  r["later_context_ms_each"] = later_ms;
  r["later_over_first_time"] = mean(later_ms) / ms[0];
  r["later_over_first_memory"] = mb[0] > 0 ? mean(later_mb) / mb[0] : 0.0;
  r["uncompiled_context_ms"] = uncompiled_ms;
  r["all_step_ms"] = mean(all);
  r["all_step_p95_ms"] = p95(all);
  r["sequential_step_ms"] = mean(seq);
  r["per_context_step_ms"] = mean(all) / C;
  r["diverged_frames"] = diverged;
  r["units"] = "ms, MB (resident-set growth)";
  return r;
}

std::string context_bench_markdown(const json& r) {
  std::ostringstream s;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "| contexts | first context ms (compile ms) | later context ms | later/first time | first MB | later MB | "
                "later/first memory | uncompiled context ms | all stepped ms/frame (p95) | sequential ms/frame |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n"
                "| %d | %.0f (%.0f) | %.0f | %.2f | %.0f | %.0f | %.2f | %.0f | %.1f (%.1f) | %.1f |\n",
                r["contexts"].get<int>(), r["first_context_ms"].get<double>(), r["compile_ms"].get<double>(),
                r["later_context_ms"].get<double>(), r["later_over_first_time"].get<double>(),
                r["first_context_mb"].get<double>(), r["later_context_mb"].get<double>(),
                r["later_over_first_memory"].get<double>(), r["uncompiled_context_ms"].get<double>(),
                r["all_step_ms"].get<double>(), r["all_step_p95_ms"].get<double>(),
                r["sequential_step_ms"].get<double>());
  s << buf << "\nDevice: " << r["device"].get<std::string>() << ".\n";
  return s.str();
}

}  // namespace facesr
