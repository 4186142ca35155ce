#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "core/error.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_metrics.h"
#include "perf/sequence_io.h"
#include "render/error_render.h"
#include "render/sequence_gltf.h"
#include "render/sequence_render.h"
#include "rig/rig_io.h"

namespace facesr::cli {
namespace {

struct RenderArgs {
  std::string rig, seq, dataset, out, gltf, frames;
  double scale_cm = 0;
  int count = 6;
  RenderOptions opt;
  bool json = false, quiet = false;
};

void require_output_folder(const std::string& path, const char* what) {
  const auto parent = std::filesystem::path(path).parent_path();
  require(parent.empty() || std::filesystem::is_directory(parent),
          std::string(what) + " folder '" + parent.string() + "' does not exist");
}

// "0,10,20" → {0, 10, 20}; names the bad item.
std::vector<int> parse_frame_list(const std::string& text) {
  std::vector<int> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t used = 0;
    int f = -1;
    try {
      f = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    require(used > 0 && used == item.size() && f >= 0,
            "--frames '" + text + "': '" + item + "' is not a frame index (expected e.g. 0,10,20)");
    out.push_back(f);
  }
  require(!out.empty(), "--frames is empty (expected e.g. 0,10,20)");
  return out;
}

// The LR-embedded surface of chosen dataset frames, coloured by its distance
// to the HR surface (what super-resolution has to make up for).
void run_render_dataset(const RenderArgs& a) {
  require_output_folder(a.out, "output");
  require(a.gltf.empty() && !a.opt.heat, "--gltf and --heat apply to --seq only");
  const Rig rig = load_rig(a.rig);
  const DatasetSequence ds = read_dataset_sequence(a.dataset);
  const int S = rig.num_surface_vertices();
  require(ds.header.num_surface == uint64_t(S) && ds.header.rig_checksum == rig_checksum(rig),
          a.dataset + ": was made with another rig than " + a.rig);
  const std::vector<int> frames =
      a.frames.empty() ? evenly_spaced_frames(ds.num_frames(), a.count) : parse_frame_list(a.frames);
  std::vector<std::vector<float>> pos, err;
  std::vector<std::string> labels;
  double worst = 0, sum = 0;
  for (int f : frames) {
    require(f < ds.num_frames(), a.dataset + ": frame " + std::to_string(f) + " is out of range (the sequence has " +
                                     std::to_string(ds.num_frames()) + " frames)");
    const DatasetFrame& fr = ds.frame(f);
    std::vector<float> p(3 * size_t(S));
    for (int v = 0; v < S; ++v)
      for (int k = 0; k < 3; ++k) p[3 * v + k] = float(rig.surface(v, k)) + fr.embedded_disp[3 * v + k];
    pos.push_back(std::move(p));
    err.push_back(embedded_error_per_vertex(fr));
    double mean, max;
    embedded_error(fr, mean, max);
    worst = std::max(worst, max);
    sum += mean;
    char label[96];
    std::snprintf(label, sizeof label, "%s frame %d  mean %.3f cm", ds.header.name.c_str(), f, mean);
    labels.push_back(label);
  }
  const double scale = a.scale_cm > 0 ? a.scale_cm : std::max(worst, 1e-6);
  render_error_png(rig, pos, err, labels, scale, a.out, a.opt.tile_width);
  if (!a.quiet) std::fprintf(stderr, "[render] wrote %s\n", a.out.c_str());
  if (a.json)
    std::printf("%s\n", nlohmann::json({{"png", a.out},
                                        {"frames", frames},
                                        {"scale_max_cm", scale},
                                        {"embedded_error_max_cm", worst},
                                        {"embedded_error_mean_cm", sum / double(frames.size())},
                                        {"units", "cm"}})
                            .dump(2)
                            .c_str());
}

void run_render(const RenderArgs& a) {
  require(a.seq.empty() != a.dataset.empty(), "give exactly one of --seq FILE.fsq or --dataset FILE.fsd");
  if (!a.dataset.empty()) return run_render_dataset(a);
  require_output_folder(a.out, "output");
  if (!a.gltf.empty()) require_output_folder(a.gltf, "glTF output");
  const Rig rig = load_rig(a.rig);
  const Sequence seq = read_sequence(a.seq);
  const int S = rig.num_surface_vertices();
  require(seq.header.num_surface == uint64_t(S), a.seq + ": has " + std::to_string(seq.header.num_surface) +
                                                     " surface vertices but rig " + a.rig + " has " +
                                                     std::to_string(S) + " (was it simulated with another rig?)");
  if (seq.header.rig_checksum != 0 && seq.header.rig_checksum != rig_checksum(rig))
    std::fprintf(stderr, "[render] warning: %s was simulated with a different rig than %s (checksums differ)\n",
                 a.seq.c_str(), a.rig.c_str());
  const std::vector<int> frames =
      a.frames.empty() ? evenly_spaced_frames(seq.frames(), a.count) : parse_frame_list(a.frames);
  for (int f : frames)
    require(f < seq.frames(), a.seq + ": frame " + std::to_string(f) + " is out of range (the sequence has " +
                                  std::to_string(seq.frames()) + " frames, 0.." + std::to_string(seq.frames() - 1) +
                                  ")");

  RenderOptions opt = a.opt;
  opt.verbose = !a.quiet;
  const RenderSummary s = render_sequence_png(rig, seq, frames, a.out, opt);
  if (!a.quiet) std::fprintf(stderr, "[render] wrote %s (%d x %d)\n", a.out.c_str(), s.width, s.height);
  if (!a.gltf.empty()) {
    // Every frame when they fit, else an even subset.
    std::vector<int> gframes;
    if (seq.frames() > kMaxGltfFrames) {
      gframes = evenly_spaced_frames(seq.frames(), kMaxGltfFrames);
      if (!a.quiet)
        std::fprintf(stderr, "[render] glTF: %d of %d frames (at most %d morph targets)\n", int(gframes.size()),
                     seq.frames(), kMaxGltfFrames);
    }
    write_sequence_gltf(rig, seq, a.gltf, gframes);
    if (!a.quiet) std::fprintf(stderr, "[render] wrote %s\n", a.gltf.c_str());
  }
  if (a.json) {
    nlohmann::json j = {{"png", a.out},       {"frames", frames}, {"width", s.width},
                        {"height", s.height}, {"units", "cm"},    {"max_displacement_cm", s.max_displacement_cm}};
    if (!a.gltf.empty()) j["gltf"] = a.gltf;
    std::printf("%s\n", j.dump(2).c_str());
  }
}

}  // namespace

void register_render(CLI::App& app) {
  static RenderArgs a;
  auto* render = app.add_subcommand("render", "Render frames of a simulated sequence (.fsq) or dataset errors (.fsd) to a PNG grid");
  render->add_option("--rig", a.rig, "Rig file the sequence was simulated with")->required();
  render->add_option("--seq", a.seq, "Sequence file (.fsq)");
  render->add_option("--dataset", a.dataset,
                     "Dataset sequence (.fsd): draw the LR-embedded surface coloured by its error against HR (cm)");
  render->add_option("--scale", a.scale_cm, "With --dataset: top of the error scale, cm (default: the largest error)");
  render->add_option("--out,-o", a.out, "Output PNG")->required();
  auto* frames = render->add_option("--frames", a.frames, "Comma-separated frame indices, e.g. 0,10,20");
  auto* count =
      render->add_option("--count", a.count, "Number of evenly spaced frames (default 6)")->check(CLI::Range(1, 1024));
  frames->excludes(count);
  render->add_option("--tile-width", a.opt.tile_width, "Pixels per frame panel (default 360)");
  render->add_option("--columns", a.opt.columns, "Panels per row (default: a near-square grid)");
  render->add_flag("--heat", a.opt.heat, "Colour by displacement from frame 0 (cm), with a legend");
  render->add_option("--gltf", a.gltf, "Also write the surface animation as glTF 2.0 (morph targets)");
  render->add_flag("--json", a.json, "JSON summary on stdout");
  render->add_flag("--quiet,-q", a.quiet, "No progress output");
  add_action(render, [] { run_render(a); });
}

}  // namespace facesr::cli
