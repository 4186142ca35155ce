#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "core/error.h"
#include "perf/livelink_csv.h"
#include "perf/performance.h"
#include "rig/rig_io.h"

namespace facesr::cli {
namespace {

struct PerfArgs {
  std::string rig, performance, builtin, out;
  bool json = false, quiet = false, strict = false;
};

// A Live Link CSV also yields its column report; `csv` stays empty otherwise.
// The report goes to stderr because unknown columns silently losing motion
// is the usual surprise with a new capture; so do the repairs' warnings, even
// with --quiet (they change the motion).
Performance load(const PerfArgs& a, const Rig& rig, nlohmann::json& csv) {
  require(a.performance.empty() != a.builtin.empty(), "give exactly one of --performance FILE and --builtin NAME");
  if (!a.builtin.empty()) return builtin_performance(a.builtin, rig.blendshape_names);
  LiveLinkReport report;
  report.rows = -1;  // stays -1 unless the file was a CSV
  LiveLinkOptions options;
  options.strict = a.strict;
  Performance p = load_performance_warned(a.performance, rig.blendshape_names, options, "perf", &report);
  if (report.rows >= 0) {
    csv = livelink_report_json(report);
    if (!a.quiet)
      std::fprintf(stderr, "[perf] %s: %s\n", a.performance.c_str(), livelink_report_summary(report).c_str());
  }
  return p;
}

void show(const PerfArgs& a) {
  const Rig rig = load_rig(a.rig);
  nlohmann::json csv;
  const Performance p = load(a, rig, csv);
  const std::vector<float> mx = max_weights(p);
  // Only the shapes the performance moves; a full ARKit list is mostly zeros.
  nlohmann::json used = nlohmann::json::object();
  for (size_t i = 0; i < mx.size(); ++i)
    if (mx[i] > 0) used[p.names[i]] = mx[i];
  if (a.json) {
    nlohmann::json j = {{"name", p.name},
                        {"source", a.builtin.empty() ? a.performance : "builtin:" + a.builtin},
                        {"frames", p.frames()},
                        {"fps", p.fps},
                        {"start_s", p.start_time},
                        {"duration_s", p.duration()},
                        {"shapes", p.names.size()},
                        {"explicit_jaw", p.has_jaw},
                        {"max_weight", used}};
    if (!csv.is_null()) j["csv"] = csv;
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("performance '%s': %d frames at %g fps, %.3f s (from t = %g s)%s\n", p.name.c_str(), p.frames(), p.fps,
              p.duration(), p.start_time, p.has_jaw ? ", explicit jaw transform" : "");
  std::printf("  %zu of the rig's %zu shapes move; max weight:\n", used.size(), p.names.size());
  for (const auto& [name, w] : used.items()) std::printf("    %-22s %.3f\n", name.c_str(), w.get<double>());
}

void write(const PerfArgs& a) {
  const auto parent = std::filesystem::path(a.out).parent_path();
  require(parent.empty() || std::filesystem::is_directory(parent),
          "output folder '" + parent.string() + "' does not exist");
  const Rig rig = load_rig(a.rig);
  nlohmann::json csv;
  const Performance p = load(a, rig, csv);
  save_performance_json(p, a.out);
  if (!a.quiet)
    std::fprintf(stderr, "[perf] wrote %s ('%s', %d frames at %g fps)\n", a.out.c_str(), p.name.c_str(), p.frames(),
                 p.fps);
  if (a.json) {
    nlohmann::json j = {{"path", a.out}, {"name", p.name}, {"frames", p.frames()}, {"fps", p.fps}};
    if (!csv.is_null()) j["csv"] = csv;
    std::printf("%s\n", j.dump(2).c_str());
  }
}

constexpr const char* kStrictHelp =
    "Refuse a Live Link CSV the default would repair (weights outside [0, 1], tracking-lost rows, repeated "
    "times, frame-index timecodes) instead of warning";

std::string builtin_list() {
  std::string s;
  for (const auto& n : builtin_performance_names()) s += (s.empty() ? "" : ", ") + n;
  return s + " (and sparse-2 ... sparse-99: more takes like sparse)";
}

}  // namespace

void register_perf(CLI::App& app) {
  auto* perf = app.add_subcommand("perf", "Inspect and write performances (blendshape weights over time)");
  perf->require_subcommand(1);

  static PerfArgs s;
  auto* show_cmd = perf->add_subcommand("show", "Load and validate a performance; print frames, duration, weights");
  show_cmd->add_option("--rig", s.rig, "Rig file (its blendshape names)")->required();
  auto* file = show_cmd->add_option("--performance", s.performance,
                                    "Keyframe JSON (.json) or Live Link Face capture (.csv, 60 fps)");
  auto* builtin = show_cmd->add_option("--builtin", s.builtin, "Built-in performance: " + builtin_list());
  file->excludes(builtin);
  show_cmd->add_flag("--json", s.json, "JSON summary on stdout");
  show_cmd->add_flag("--strict", s.strict, kStrictHelp);
  add_action(show_cmd, [] { show(s); });

  static PerfArgs w;
  auto* write_cmd = perf->add_subcommand(
      "write", "Save a built-in performance, or a converted .json/.csv performance, as keyframe JSON");
  write_cmd->add_option("--rig", w.rig, "Rig file (its blendshape names)")->required();
  auto* wfile = write_cmd->add_option(
      "--performance", w.performance, "Keyframe JSON (.json) or Live Link Face capture (.csv, 60 fps; resampled to 30)");
  auto* wbuiltin = write_cmd->add_option("--builtin", w.builtin, "Built-in performance: " + builtin_list());
  wfile->excludes(wbuiltin);
  write_cmd->add_option("--out,-o", w.out, "Output JSON file")->required();
  write_cmd->add_flag("--json", w.json, "JSON summary on stdout");
  write_cmd->add_flag("--strict", w.strict, kStrictHelp);
  write_cmd->add_flag("--quiet,-q", w.quiet, "No progress output");
  add_action(write_cmd, [] { write(w); });
}

}  // namespace facesr::cli
