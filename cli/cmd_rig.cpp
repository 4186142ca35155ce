#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "core/error.h"
#include "rig/rig_build.h"
#include "rig/rig_io.h"
#include "rig/rig_preset.h"
#include "render/rig_preview.h"
#include "rig/rig_summary.h"

namespace facesr::cli {
namespace {

struct BuildArgs {
  RigBuildOptions opt;
  std::string out;
  std::string preview;
  std::string preset = "default";
  bool json = false;
};

void apply_preset(BuildArgs& a) { apply_rig_preset(a.opt, a.preset); }

void print_summary(const Rig& rig, bool json) {
  const auto s = rig_summary(rig);
  if (json) {
    std::printf("%s\n", s.dump(2).c_str());
    return;
  }
  std::printf("rig '%s' (units: %s)\n", rig.name.c_str(), rig.units.c_str());
  for (const char* k : {"hr_tets", "hr_vertices", "lr_tets", "lr_vertices", "hr_over_lr_tets", "surface_vertices",
                        "embedded_outside_lr", "hr_min_dihedral_deg", "lr_min_dihedral_deg", "inverted_tets", "muscles",
                        "muscle_tets_hr", "muscle_tets_lr", "dirichlet_nodes_hr", "dirichlet_nodes_lr", "blendshapes",
                        "predeform_angle_deg", "build_seconds"})
    if (s.contains(k)) std::printf("  %-22s %s\n", k, s[k].dump().c_str());
}

}  // namespace

void register_rig(CLI::App& app) {
  auto* rig = app.add_subcommand("rig", "Build and inspect anatomical face rigs");
  rig->require_subcommand(1);

  static BuildArgs b;
  auto* build = rig->add_subcommand("build", "Build a rig from a head (ICT FaceKit folder or 'procedural')");
  build->add_option("--source", b.opt.source, "ICT FaceKit folder, or 'procedural' for the built-in head")->required();
  build->add_option("--out,-o", b.out, "Output rig file")->required();
  build->add_option("--muscles", b.opt.muscles_path, "Muscle specification JSON (default: built-in)");
  build->add_option("--preset", b.preset, "default | coarse (small rig for tests)");
  build->add_option("--lr-cell", b.opt.lr_cell, "LR lattice cell size (cm)");
  build->add_option("--hr-max-volume", b.opt.hr_max_volume, "HR tet volume bound (cm^3)");
  build->add_option("--flesh-grid", b.opt.flesh_grid_h, "Flesh signed-distance grid spacing (cm)");
  build->add_option("--preview", b.preview, "Also render a PNG preview of the rig");
  build->add_flag("--json", b.json, "Print the rig summary as JSON on stdout");
  build->add_flag("--quiet,-q", [](int64_t) { b.opt.verbose = false; }, "No progress output");
  add_action(build, [build] {
    // Options given on the command line win over the preset's values.
    BuildArgs a = b;
    apply_preset(a);
    if (build->count("--lr-cell")) a.opt.lr_cell = b.opt.lr_cell;
    if (build->count("--hr-max-volume")) a.opt.hr_max_volume = b.opt.hr_max_volume;
    if (build->count("--flesh-grid")) a.opt.flesh_grid_h = b.opt.flesh_grid_h;
    const auto parent = std::filesystem::path(a.out).parent_path();
    require(parent.empty() || std::filesystem::is_directory(parent),
            "output folder '" + parent.string() + "' does not exist");
    Rig r = build_rig(a.opt);
    save_rig(r, a.out);
    if (!a.preview.empty()) render_rig_preview(r, a.preview, PreviewOptions{});
    if (a.opt.verbose) std::fprintf(stderr, "[rig] built in %.1f s, wrote %s\n", r.build_seconds, a.out.c_str());
    print_summary(r, a.json);
  });

  static std::string info_path;
  static bool info_json = false;
  auto* info = rig->add_subcommand("info", "Print a rig file's summary");
  info->add_option("rig", info_path, "Rig file")->required();
  info->add_flag("--json", info_json, "JSON on stdout");
  add_action(info, [] { print_summary(load_rig(info_path), info_json); });

  static std::string pv_rig, pv_out;
  static PreviewOptions pv_opt;
  auto* preview = rig->add_subcommand("preview", "Render a rig's face, muscles and LR lattice to a PNG");
  preview->add_option("rig", pv_rig, "Rig file")->required();
  preview->add_option("--out,-o", pv_out, "Output PNG")->required();
  preview->add_option("--width", pv_opt.width, "Image width (pixels)");
  preview->add_option("--height", pv_opt.height, "Image height (pixels)");
  static bool pv_json = false;
  preview->add_flag("--json", pv_json, "JSON summary on stdout");
  add_action(preview, [] {
    const Rig r = load_rig(pv_rig);
    render_rig_preview(r, pv_out, pv_opt);
    if (pv_json)
      std::printf("%s\n", nlohmann::json({{"png", pv_out}, {"width", pv_opt.width}, {"height", pv_opt.height},
                                          {"muscles", r.muscles.size()}, {"units", r.units}})
                               .dump(2)
                               .c_str());
  });
}

}  // namespace facesr::cli
