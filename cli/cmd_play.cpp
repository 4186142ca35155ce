// facesr play and facesr bench runtime: a performance through the real-time
// runtime (engine/runtime), as a game would drive it.
#include <chrono>
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "bench/bench_report.h"
#include "bench/context_bench.h"
#include "bench/runtime_bench.h"
#include "commands.h"
#include "core/error.h"
#include "core/progress.h"
#include "collide/mouth_collider.h"
#include "dataset/dataset_manifest.h"
#include "perf/livelink_csv.h"
#include "perf/perf_controls.h"
#include "perf/performance.h"
#include "render/sequence_gltf.h"
#include "rig/rig_io.h"
#include "runtime/runtime_context.h"
#include "sr/sr_model.h"

namespace facesr::cli {

namespace {

struct RuntimeArgs {
  std::string rig, model, builtin, performance, device, solver = "realtime", lr_precision = "auto";
  bool cpu_inference = false, split_device = false, strict = false, no_recover = false;
  void add(CLI::App* sub) {
    sub->add_option("--rig", rig, "Rig file")->required();
    sub->add_option("--model", model, "Trained network (.fsm) for this rig")->required();
    sub->add_option("--builtin", builtin, "Built-in performance (default talk)");
    sub->add_option("--performance", performance, "Performance file: keyframe JSON or Live Link Face CSV");
    sub->add_flag("--strict", strict,
                  "Refuse a Live Link CSV the default would repair (weights outside [0, 1], tracking-lost rows, "
                  "repeated times, frame-index timecodes) instead of warning");
    sub->add_option("--device", device, "OpenCL device: index, name, cpu or gpu (default: first CPU device)");
    sub->add_option("--solver", solver, "realtime (default) | accurate");
    sub->add_option("--lr-precision", lr_precision,
                    "LR simulation arithmetic: auto (float with the realtime solver, double with accurate) | "
                    "double | float");
    sub->add_flag("--no-recover", no_recover,
                  "Divergence detection and recovery off (to measure their cost; a diverged frame is then returned as is)");
    sub->add_flag("--cpu-inference", cpu_inference, "The C++ reference inference instead of the OpenCL kernels");
    sub->add_flag("--split-device", split_device,
                  "Half the device's compute units for the simulation, half for the inference (faster with "
                  "--async on a CPU, slower without)");
  }
  RuntimeOptions options() const {
    RuntimeOptions o;
    o.device = compute::DeviceSelector::parse(device);
    require(solver == "realtime" || solver == "accurate", "--solver must be realtime or accurate, not '" + solver + "'");
    o.solver = solver == "realtime" ? realtime_solver() : SolverOptions{};
    o.solver.recover = !no_recover;
    o.cpu_inference = cpu_inference;
    o.split_device = split_device;
    require(lr_precision == "auto" || lr_precision == "double" || lr_precision == "float",
            "--lr-precision must be auto, double or float, not '" + lr_precision + "'");
    o.lr_single_precision = lr_precision == "float" || (lr_precision == "auto" && solver == "realtime");
    return o;
  }
  // The repairs' warnings go to stderr even with --quiet: they change the motion.
  Performance load(const Rig& rig) const {
    require(builtin.empty() || performance.empty(), "give --builtin or --performance, not both");
    if (performance.empty()) return builtin_performance(builtin.empty() ? "talk" : builtin, rig.blendshape_names);
    LiveLinkOptions o;
    o.strict = strict;
    return load_performance_warned(performance, rig.blendshape_names, o, "play");
  }
};

void apply(RuntimeContext& ctx, const Performance& p, int f, const Jaw& jaw) {
  Controls c;
  frame_controls(p, f, jaw, c);
  ctx.set_weights(c.weights);
  if (c.jaw_override)
    ctx.set_jaw(c.jaw_R, c.jaw_t);
  else
    ctx.clear_jaw();
}

}  // namespace

void register_play(CLI::App& app) {
  struct Args {
    RuntimeArgs rt;
    std::string out;
    int frames = 0;
    bool async = false, json = false, quiet = false;
  };
  static Args a;
  auto* sub = app.add_subcommand("play", "Play a performance through the real-time runtime (LR simulation + "
                                         "super-resolution) and write the animated HR surface as glTF");
  a.rt.add(sub);
  sub->add_option("--out,-o", a.out, "Output glTF (.gltf, morph-target animation, cm in a 0.01-scaled node)");
  sub->add_option("--frames", a.frames, "Play only the first N frames");
  sub->add_flag("--async", a.async, "Pipeline: simulate frame t+1 while super-resolving frame t");
  sub->add_flag("--json", a.json, "Print a JSON summary: frames, fps, mean_simulation_ms, mean_inference_ms, diverged_frames, recovered_frames, "
                "unconverged_frames, device; exit status 1 when any frame diverged");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  add_action(sub, [] {
    require(a.frames >= 0, "--frames must be >= 0");
    auto rig = std::make_shared<const Rig>(load_rig(a.rt.rig));
    auto model = std::make_shared<const SrModel>(load_sr_model(a.rt.model));
    const Performance perf = a.rt.load(*rig);
    const int F = a.frames > 0 ? std::min(a.frames, perf.frames()) : perf.frames();
    require(!a.out.empty() || a.json || !a.quiet, "nothing to do: give --out or --json");
    if (!a.out.empty()) require(F <= kMaxGltfFrames, "a glTF holds at most " + std::to_string(kMaxGltfFrames) +
                                                         " frames; use --frames");
    RuntimeContext ctx(rig, model, a.rt.options());
    Sequence seq;
    seq.header.resolution = "high";
    seq.header.rig_checksum = rig_checksum(*rig);
    seq.header.fps = perf.fps;
    seq.header.num_surface = uint64_t(rig->num_surface_vertices());
    double sim_ms = 0, sr_ms = 0;
    int diverged = 0, recovered = 0, unconverged = 0;
    auto keep = [&] {
      const FrameResult& r = ctx.result();
      diverged += r.status == StepStatus::Diverged;
      recovered += r.status == StepStatus::Recovered;
      unconverged += r.status == StepStatus::Unconverged;
      seq.time.push_back(perf.time(int(r.frame)));
      seq.surface.insert(seq.surface.end(), r.positions.begin(), r.positions.end());
      sim_ms += r.simulation_ms;
      sr_ms += r.inference_ms;
    };
    Progress progress("play", F, !a.quiet);
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < F; ++f) {
      apply(ctx, perf, f, rig->jaw);
      if (a.async) {
        ctx.step_async();
        if (ctx.pending() == 2) {
          ctx.wait();
          keep();
        }
      } else {
        ctx.step();
        keep();
      }
      progress.update(f + 1);
    }
    while (ctx.pending() > 0) {
      ctx.wait();
      keep();
    }
    const double wall = seconds_since(t0);
    progress.finish();
    if (!a.out.empty()) write_sequence_gltf(*rig, seq, a.out);
    const double fps = F / wall;
    nlohmann::json j = {{"frames", F},
                        {"fps", fps},
                        {"wall_s", wall},
                        {"mean_simulation_ms", sim_ms / F},
                        {"mean_inference_ms", sr_ms / F},
                        {"async", a.async},
                        {"diverged_frames", diverged},
                        {"recovered_frames", recovered},
                        {"unconverged_frames", unconverged},
                        {"device", ctx.device()},
                        {"out", a.out},
                        {"units", "cm"}};
    if (a.json)
      std::printf("%s\n", j.dump(2).c_str());
    else
      std::printf("played %d frames at %.1f FPS (simulation %.1f ms, super-resolution %.1f ms per frame%s)%s%s\n", F,
                  fps, sim_ms / F, sr_ms / F, a.async ? ", pipelined" : "", a.out.empty() ? "" : "; wrote ",
                  a.out.c_str());
    if (diverged > 0)
      throw Error(std::to_string(diverged) + " of " + std::to_string(F) +
                  " frames diverged; the runtime returned the last good surface for them (see diverged_frames)");
  });
}

void add_bench_runtime(CLI::App* bench) {
  struct Args {
    RuntimeArgs rt;
    std::string dataset, markdown;
    int frames = 60, hr_frames = 0, hr_skip = 30;
    bool json = false, quiet = false;
  };
  static Args a;
  auto* sub = bench->add_subcommand("runtime", "Real-time runtime: LR step, super-resolution, end-to-end and "
                                               "pipelined FPS, speed-up over the HR simulation");
  a.rt.add(sub);
  sub->add_option("--dataset", a.dataset, "Dataset whose HR step times give hr_step_ms (from its manifest)");
  sub->add_option("--frames", a.frames, "Timed frames per mode (default 60)");
  sub->add_option("--hr-frames", a.hr_frames,
                  "Time this many HR reference frames (CPU, with collisions) instead of reading a dataset");
  sub->add_option("--hr-skip", a.hr_skip, "Untimed HR frames simulated first, from the rest pose (default 30)");
  sub->add_option("--markdown", a.markdown, "Write the results into this Markdown file (e.g. BENCHMARKS.md)");
  sub->add_flag("--json", a.json,
                "Print JSON: lr_step_ms, sr_ms, end_to_end_ms, end_to_end_fps, pipelined_fps, hr_step_ms, "
                "speedup_vs_hr");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  add_action(sub, [] {
    require(a.frames > 0, "--frames must be positive");
    auto rig = std::make_shared<const Rig>(load_rig(a.rt.rig));
    auto model = std::make_shared<const SrModel>(load_sr_model(a.rt.model));
    const Performance perf = a.rt.load(*rig);
    std::vector<std::vector<float>> w;
    for (int f = 0; f < perf.frames(); ++f) w.emplace_back(perf.frame(f), perf.frame(f) + perf.names.size());
    RuntimeBenchOptions o;
    o.frames = a.frames;
    o.runtime = a.rt.options();
    o.progress = !a.quiet;
    if (!a.dataset.empty()) {
      const DatasetManifest m = load_manifest(a.dataset + "/manifest.json");
      require(m.rig_checksum == rig_checksum(*rig), a.dataset + ": the dataset is of another rig");
      double s = 0;
      int n = 0;
      for (const auto& e : m.sequences)
        if (e.hr_mean_step_s > 0) {
          s += e.hr_mean_step_s * e.frames;
          n += e.frames;
        }
      require(n > 0, a.dataset + ": the manifest has no HR step times");
      o.hr_step_ms = 1e3 * s / n;
      o.hr_source = "mean of " + std::to_string(n) + " HR frames in " + a.dataset + " (CPU, with collisions)";
    }
    if (a.hr_frames > 0) {
      const SimModel hr_model = make_sim_model(*rig, Resolution::High);
      auto collider = std::make_shared<MouthCollider>(*rig, hr_model);
      auto hr = make_cpu_simulator(hr_model, SolverOptions{}, collider, true);
      Controls c;
      double ms = 0;
      Progress hp("bench HR reference", a.hr_skip + a.hr_frames, !a.quiet);
      for (int f = 0; f < a.hr_skip + a.hr_frames; ++f) {
        frame_controls(perf, f % perf.frames(), rig->jaw, c);
        const StepStats st = hr->step(c);
        if (f >= a.hr_skip) ms += st.ms;
        hp.update(f + 1);
      }
      o.hr_step_ms = ms / a.hr_frames;
      o.hr_source = "fresh run of " + std::to_string(a.hr_frames) + " HR frames (frames " + std::to_string(a.hr_skip) +
                    "+ of the performance; CPU, with collisions, accurate solver)";
    }
    nlohmann::json r = bench_runtime(rig, model, w, o);
    r["rig"] = rig->name;
    r["solver_preset"] = a.rt.solver;
    if (!a.markdown.empty()) update_markdown_section(a.markdown, "bench-runtime-" + rig->name + "-" + machine_slug(), runtime_bench_markdown(r));
    if (a.json)
      std::printf("%s\n", r.dump(2).c_str());
    else
      std::printf("%s", runtime_bench_markdown(r).c_str());
  });
}

void add_bench_contexts(CLI::App* bench) {
  struct Args {
    RuntimeArgs rt;
    std::string markdown;
    int contexts = 4, frames = 30;
    bool json = false, quiet = false;
  };
  static Args a;
  auto* sub = bench->add_subcommand("contexts", "Several characters on one rig and model: the cost of the first "
                                                "context against later ones (which share the compiled model), and "
                                                "of stepping them all each frame");
  a.rt.add(sub);
  sub->add_option("--contexts", a.contexts, "Characters, a context each (default 4)");
  sub->add_option("--frames", a.frames, "Timed frames (default 30)");
  sub->add_option("--markdown", a.markdown, "Write the results into this Markdown file (e.g. BENCHMARKS.md)");
  sub->add_flag("--json", a.json,
                "Print JSON: first_context_ms, later_context_ms, later_over_first_time, later_over_first_memory, "
                "all_step_ms, sequential_step_ms");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  add_action(sub, [] {
    auto rig = std::make_shared<const Rig>(load_rig(a.rt.rig));
    auto model = std::make_shared<const SrModel>(load_sr_model(a.rt.model));
    const Performance perf = a.rt.load(*rig);
    std::vector<std::vector<float>> w;
    for (int f = 0; f < perf.frames(); ++f) w.emplace_back(perf.frame(f), perf.frame(f) + perf.names.size());
    ContextBenchOptions o;
    o.contexts = a.contexts;
    o.frames = a.frames;
    o.runtime = a.rt.options();
    o.progress = !a.quiet;
    nlohmann::json r = bench_contexts(rig, model, w, o);
    r["rig"] = rig->name;
    if (!a.markdown.empty())
      update_markdown_section(a.markdown, "bench-contexts-" + rig->name + "-" + machine_slug(), context_bench_markdown(r));
    if (a.json)
      std::printf("%s\n", r.dump(2).c_str());
    else
      std::printf("%s", context_bench_markdown(r).c_str());
    if (r["diverged_frames"].get<int>() > 0)
      throw Error(std::to_string(r["diverged_frames"].get<int>()) + " frames diverged (see diverged_frames)");
  });
}

}  // namespace facesr::cli
