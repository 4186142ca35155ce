// facesr dataset: the paired LR/HR training data (engine/dataset/generate.h).
#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/error.h"
#include "dataset/generate.h"
#include "rig/rig_io.h"

namespace facesr::cli {
namespace {
std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : s + ",") {
    if (ch == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(ch);
    }
  }
  return out;
}
}  // namespace

void register_dataset(CLI::App& app) {
  struct Args {
    std::string rig, out, builtins, test = "anger,fear", device;
    std::vector<std::string> files;
    int frames = 0;
    bool restart = false, no_collisions = false, lr_cpu = false, json = false, quiet = false;
  };
  static Args a;
  auto* sub = app.add_subcommand("dataset", "Simulate performances on LR and HR and write the paired dataset");
  sub->add_option("--rig", a.rig, "Rig file")->required();
  sub->add_option("--out,-o", a.out, "Output folder (one .fsd per performance + manifest.json)")->required();
  sub->add_option("--builtin", a.builtins,
                  "Comma-separated built-in performances (default amazement,anger,fear,pain when no --performance)");
  sub->add_option("--performance", a.files, "Performance file(s): keyframe JSON or Live Link Face CSV");
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
  add_action(sub, [] {
    require(a.frames >= 0, "--frames must be >= 0");
    const Rig rig = load_rig(a.rig);
    DatasetOptions o;
    o.builtins = split_list(a.builtins);
    o.files = a.files;
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
