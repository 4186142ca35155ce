#include "bench/runtime_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "bench/bench_report.h"
#include "bench/bench_stats.h"
#include "core/error.h"
#include "core/progress.h"
#include "runtime/sr_inference.h"

namespace facesr {

using nlohmann::json;

namespace {

using bench_stats::mean;
using bench_stats::p95;

}  // namespace

json bench_runtime(std::shared_ptr<const Rig> rig, std::shared_ptr<const SrModel> model,
                   const std::vector<std::vector<float>>& weights, const RuntimeBenchOptions& opt) {
  require(opt.frames > 0 && opt.warmup >= 0, "bench runtime: frames must be positive");
  require(!weights.empty(), "bench runtime: no performance frames");
  const int total = opt.warmup + opt.frames;
  auto frame_weights = [&](int f) -> const std::vector<float>& { return weights[size_t(f) % weights.size()]; };
  RuntimeContext ctx(rig, model, opt.runtime);
  Progress progress("bench runtime", 3 * total, opt.progress);
  int progress_done = total;

  // Synchronous: each frame simulated then super-resolved.
  std::vector<double> sim, sr, e2e, newton;
  int diverged = 0;  // over every frame stepped, timed or not
  for (int f = 0; f < total; ++f) {
    ctx.set_weights(frame_weights(f));
    const auto t0 = std::chrono::steady_clock::now();
    ctx.step();
    const double ms = 1e3 * seconds_since(t0);
    diverged += ctx.result().status == StepStatus::Diverged;
    if (f >= opt.warmup) {
      sim.push_back(ctx.result().simulation_ms);
      sr.push_back(ctx.result().inference_ms);
      e2e.push_back(ms);
      newton.push_back(ctx.result().newton_iterations);
    }
    progress.update(f + 1, "sync");
  }

  // Pipelined: frame t+1 simulates while frame t super-resolves; once with
  // the stages sharing the whole device, once with half of it each.
  auto pipelined = [&](RuntimeContext& c, const char* label) {
    c.reset();
    std::chrono::steady_clock::time_point t_start;
    for (int f = 0; f < total; ++f) {
      if (f == opt.warmup) t_start = std::chrono::steady_clock::now();
      c.set_weights(frame_weights(f));
      c.step_async();
      if (c.pending() == 2) {
        c.wait();
        diverged += c.result().status == StepStatus::Diverged;
      }
      progress.update(progress_done + f + 1, label);
    }
    while (c.pending() > 0) {
      c.wait();
      diverged += c.result().status == StepStatus::Diverged;
    }
    progress_done += total;
    return double(opt.frames) / seconds_since(t_start);
  };
  const double shared_fps = pipelined(ctx, "pipelined");
  RuntimeOptions split_opt = opt.runtime;
  split_opt.split_device = true;
  RuntimeContext split_ctx(rig, model, split_opt);
  const std::string split_device = split_ctx.device();
  const bool did_split = split_device != ctx.device();
  const double split_fps = did_split ? pipelined(split_ctx, "pipelined, split device") : 0.0;
  progress.finish();
  const double pipelined_fps = std::max(shared_fps, split_fps);
  const double pipelined_s = double(opt.frames) / pipelined_fps;

  // Where the inference time goes (a separately profiled instance; stage
  // waits make it a little slower than the unprofiled runs above).
  json stages = json::array();
  if (!opt.runtime.cpu_inference) {
    ClInferenceOptions io;
    io.device = opt.runtime.device;
    io.profile = true;
    auto inf = make_cl_inference(model, io);
    std::vector<float> in(size_t(3 * model->num_lr), 0.0f), out(size_t(3 * model->num_hr));
    // The network's cost does not depend on its input; the correctives' does.
    // Their worst case: every shape just off rest, between its first two
    // samples (two residuals each), so profile that pose rather than rest.
    const RestCorrectives& rc = model->rest_correctives;
    const size_t N3 = in.size();
    for (int s = 0; s < rc.count(); ++s) {
      const auto& a = rc.amplitudes[size_t(s)];
      const float w = a.size() > 1 ? 0.5f * (a[0] + a[1]) : 0.5f * a[0];
      for (size_t i = 0; i < N3; ++i) in[i] += w * rc.lr[size_t(s) * N3 + i];
    }
    std::vector<std::pair<std::string, double>> sum;
    const int reps = 10;
    for (int r = 0; r < reps + 1; ++r) {
      inf->infer(in.data(), out.data());
      if (r == 0) continue;  // warm-up
      const auto p = inf->last_profile();
      if (sum.empty()) sum = p;
      else
        for (size_t i = 0; i < p.size() && i < sum.size(); ++i) sum[i].second += p[i].second;
    }
    for (const auto& [name, ms] : sum) stages.push_back({{"stage", name}, {"ms", ms / reps}});
  }

  json r;
  r["frames"] = opt.frames;
  r["lr_step_ms"] = mean(sim);
  r["lr_step_p95_ms"] = p95(sim);
  r["lr_newton_iters"] = mean(newton);
  r["diverged_frames"] = diverged;
  r["sr_ms"] = mean(sr);
  r["sr_p95_ms"] = p95(sr);
  r["end_to_end_ms"] = mean(e2e);
  r["end_to_end_p95_ms"] = p95(e2e);
  r["end_to_end_fps"] = 1e3 / mean(e2e);
  r["pipelined_fps"] = pipelined_fps;
  r["pipelined_shared_fps"] = shared_fps;
  r["pipelined_split_fps"] = did_split ? json(split_fps) : json(nullptr);
  r["pipelined_mode"] = split_fps > shared_fps ? "split device" : "shared device";
  r["split_device"] = did_split ? json(split_device) : json(nullptr);
  r["hr_step_ms"] = opt.hr_step_ms;
  r["hr_source"] = opt.hr_source;
  r["speedup_vs_hr"] = opt.hr_step_ms > 0 ? opt.hr_step_ms / mean(e2e) : -1;
  r["pipelined_speedup_vs_hr"] = opt.hr_step_ms > 0 ? opt.hr_step_ms * (double(opt.frames) / pipelined_s) / 1e3 : -1;
  r["sr_stages"] = stages;
  r["device"] = ctx.device();
  r["lr_nodes"] = model->num_lr;
  r["hr_vertices"] = model->num_hr;
  r["machine"] = machine_description();
  r["date"] = today_iso();
  r["units"] = "ms";
  return r;
}

std::string runtime_bench_markdown(const json& r) {
  std::ostringstream md;
  char line[512];
  md << "### Runtime (`facesr bench runtime`)\n\n";
  md << "Measured " << r.value("date", "") << " on " << r.value("machine", "") << ". Rig `" << r.value("rig", "")
     << "` (" << r.value("lr_nodes", 0) << " LR nodes, " << r.value("hr_vertices", 0)
     << " HR surface vertices), device " << r.value("device", "") << ", solver preset "
     << r.value("solver_preset", "realtime") << "; " << r.value("frames", 0)
     << " timed frames of a built-in performance after warm-up.\n\n";
  md << "| LR step ms | SR ms | end-to-end ms | end-to-end FPS | pipelined FPS | HR step ms | speed-up vs HR |\n"
        "|---|---|---|---|---|---|---|\n";
  std::snprintf(line, sizeof line, "| %.1f | %.1f | %.1f | %.1f | %.1f | %.0f | %.0f× |\n\n",
                r.value("lr_step_ms", 0.0), r.value("sr_ms", 0.0), r.value("end_to_end_ms", 0.0),
                r.value("end_to_end_fps", 0.0), r.value("pipelined_fps", 0.0), r.value("hr_step_ms", 0.0),
                r.value("speedup_vs_hr", 0.0));
  md << line;
  std::snprintf(line, sizeof line, "Pipelined (`step_async`): %.1f FPS with both stages on the whole device",
                r.value("pipelined_shared_fps", 0.0));
  md << line;
  if (r.contains("pipelined_split_fps") && r["pipelined_split_fps"].is_number()) {
    std::snprintf(line, sizeof line, ", %.1f FPS with half of it each (`split_device`)",
                  r["pipelined_split_fps"].get<double>());
    md << line;
  } else {
    md << " (the device cannot be split)";
  }
  md << "; the table gives the better.\n\n";
  md << "HR step time: " << r.value("hr_source", std::string("not measured")) << ".\n\n";
  if (r.contains("sr_stages") && !r["sr_stages"].empty()) {
    const bool corrected = r["sr_stages"].back().value("stage", std::string()) == "rest correctives";
    md << "Inference stages (profiled run, ms" << (corrected ? "; at a pose with every rest corrective active" : "")
       << "): ";
    bool first = true;
    for (const auto& s : r["sr_stages"]) {
      std::snprintf(line, sizeof line, "%s%s %.2f", first ? "" : ", ", s["stage"].get<std::string>().c_str(),
                    s["ms"].get<double>());
      md << line;
      first = false;
    }
    md << ".\n\n";
  }
  const double fps = r.value("end_to_end_fps", 0.0), pfps = r.value("pipelined_fps", 0.0);
  std::snprintf(line, sizeof line,
                "Goals: end-to-end ≥ 30 FPS (measured %.1f: %s), pipelined higher (%.1f: %s), speed-up vs HR > 78× "
                "(measured %.0f×: %s).\n",
                fps, fps >= 30 ? "met" : "missed", pfps, pfps > fps ? "higher" : "not higher",
                r.value("speedup_vs_hr", 0.0), r.value("speedup_vs_hr", 0.0) > 78 ? "met" : "missed");
  md << line;
  return md.str();
}

}  // namespace facesr
