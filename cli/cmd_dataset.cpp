// facesr dataset: the paired LR/HR training data (engine/dataset/generate.h).
#include <cstdio>

#include <nlohmann/json.hpp>

#include <sstream>

#include "bench/bench_report.h"
#include "arg_lists.h"
#include "commands.h"
#include "core/error.h"
#include "dataset/dataset_manifest.h"
#include "dataset/generate.h"
#include "rig/rig_io.h"

namespace facesr::cli {
namespace {
// The BENCHMARKS.md section of a dataset run: totals and one row per sequence.
std::string dataset_markdown(const nlohmann::json& j, const DatasetManifest& m) {
  std::ostringstream md;
  char line[512];
  md << "Measured " << j.value("date", "") << " on " << j.value("machine", "") << ". Rig `" << m.rig_name
     << "`: LR " << m.num_lr_nodes << " nodes on " << j.value("lr_device", "") << "; HR on "
     << j.value("hr_device", "") << ". Solver: accurate preset on both (Newton tolerance 1e-3).\n\n";
  md << "| sequence | split | frames | HR s/frame | LR ms/frame | HR/LR | embedded error mean (cm) | max (cm) | "
        "max penetration (cm) |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& e : m.sequences) {
    std::snprintf(line, sizeof line, "| %s | %s | %d | %.2f | %.1f | %.0f× | %.4f | %.3f | %.3f |\n", e.name.c_str(),
                  e.split.c_str(), e.frames, e.hr_mean_step_s, e.lr_mean_step_ms,
                  e.lr_mean_step_ms > 0 ? 1e3 * e.hr_mean_step_s / e.lr_mean_step_ms : 0.0,
                  e.embedded_error_mean_cm, e.embedded_error_max_cm, e.max_penetration_cm);
    md << line;
  }
  std::snprintf(line, sizeof line,
                "| **all** | | %d | %.2f | %.1f | **%.0f×** | %.4f | %.3f | %.3f |\n\n",
                j.value("frames", 0), j.value("hr_mean_step_s", 0.0), j.value("lr_mean_step_ms", 0.0),
                j.value("hr_over_lr_time", 0.0), j.value("embedded_error_mean_cm", 0.0),
                j.value("embedded_error_max_cm", 0.0), j.value("max_penetration_cm", 0.0));
  md << line;
  std::snprintf(line, sizeof line,
                "Simulation time (sum of LR and HR step times): %.1f min. Wall time of the last run: %.1f min "
                "(%d frames were resumed from an earlier, interrupted run; %d sequences were already complete). "
                "NaN frames: %d; diverged frames: %d; HR frames stopped above the Newton tolerance: %d (left out of training). "
                "The paper reports HR/LR = 188×.\n",
                j.value("frames", 0) * (j.value("hr_mean_step_s", 0.0) + j.value("lr_mean_step_ms", 0.0) / 1e3) / 60,
                j.value("wall_s", 0.0) / 60, j.value("resumed_frames", 0), j.value("skipped_sequences", 0),
                j.value("nan_frames", 0), j.value("diverged_frames", 0), j.value("hr_capped_frames", 0));
  md << line;
  return md.str();
}

}  // namespace

void register_dataset(CLI::App& app) {
  struct Args {
    std::string rig, out, builtins, test = "anger,fear", device, markdown;
    std::vector<std::string> files;
    int frames = 0;
    bool restart = false, no_collisions = false, lr_cpu = false, json = false, quiet = false, strict = false;
  };
  static Args a;
  auto* sub = app.add_subcommand("dataset", "Simulate performances on LR and HR and write the paired dataset");
  sub->add_option("--rig", a.rig, "Rig file")->required();
  sub->add_option("--out,-o", a.out, "Output folder (one .fsd per performance + manifest.json)")->required();
  sub->add_option("--builtin", a.builtins,
                  "Comma-separated built-in performances (default amazement,anger,fear,pain when no --performance)");
  sub->add_option("--performance", a.files, "Performance file(s): keyframe JSON or Live Link Face CSV");
  sub->add_flag("--strict", a.strict,
                "Refuse a Live Link CSV the default would repair (weights outside [0, 1], tracking-lost rows, "
                "repeated times, frame-index timecodes) instead of warning");
  sub->add_option("--test", a.test, "Comma-separated performances of the test split (default anger,fear)");
  sub->add_option("--frames", a.frames, "Only the first N frames of each performance");
  sub->add_option("--device", a.device, "OpenCL device for the LR simulation");
  sub->add_flag("--lr-cpu", a.lr_cpu, "LR on the CPU reference instead of OpenCL");
  sub->add_flag("--no-collisions", a.no_collisions, "HR without collision handling (penetration still measured)");
  sub->add_flag("--restart", a.restart, "Discard finished and partial sequences in the folder instead of resuming");
  sub->add_flag("--json", a.json,
                "Print a JSON summary: frames, sequences, hr_mean_step_s, lr_mean_step_ms, hr_over_lr_time, "
                "embedded_error_mean_cm, embedded_error_max_cm");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  sub->add_option("--markdown", a.markdown, "Record the run in this Markdown file (e.g. BENCHMARKS.md)");
  add_action(sub, [] {
    require(a.frames >= 0, "--frames must be >= 0");
    const Rig rig = load_rig(a.rig);
    DatasetOptions o;
    o.builtins = split_list(a.builtins);
    o.files = a.files;
    o.csv.strict = a.strict;
    if (o.builtins.empty() && o.files.empty()) o.builtins = {"amazement", "anger", "fear", "pain"};
    o.test_names = split_list(a.test);
    o.max_frames = a.frames;
    o.restart = a.restart;
    o.collisions = !a.no_collisions;
    o.lr_cpu = a.lr_cpu;
    o.device = a.device;
    o.progress = !a.quiet;
    const DatasetSummary s = generate_dataset(rig, a.rig, a.out, o);
    nlohmann::json j = s.to_json();
    j["out"] = a.out;
    j["machine"] = machine_description();
    j["date"] = today_iso();
    if (!a.markdown.empty()) {
      // Timings are per machine: one section per rig and CPU, as for the benchmarks.
      update_markdown_section(a.markdown, "dataset-" + rig.name + "-" + machine_slug(),
                              dataset_markdown(j, load_manifest(a.out + "/manifest.json")));
    }
    if (a.json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("wrote %s: %d sequences, %d frames; HR %.2f s/frame, LR %.1f ms/frame (HR/LR %.0fx); "
                  "embedded vs HR error mean %.3f cm, max %.3f cm; max penetration %.3f cm\n",
                  a.out.c_str(), s.sequences, s.frames, s.hr_mean_step_s, s.lr_mean_step_ms, s.hr_over_lr_time,
                  s.embedded_error_mean_cm, s.embedded_error_max_cm, s.max_penetration_cm);
    }
  });
}

}  // namespace facesr::cli
