// `facesr character build`: a head to a packaged real-time model in one
// resumable command (engine/character).
#include <cstdio>

#include <nlohmann/json.hpp>

#include "character/character_build.h"
#include "character/character_recipe.h"
#include "commands.h"

namespace facesr::cli {

void register_character(CLI::App& app) {
  auto* ch = app.add_subcommand("character", "Make a real-time model for your own character");
  ch->require_subcommand(1);
  struct Args {
    CharacterOptions o;
    std::string budget = "3h";
    bool json = false, quiet = false;
  };
  static Args a;
  auto* b = ch->add_subcommand(
      "build",
      "Head → rig → paired dataset → training → post-fit → test evaluation → package, sized to a time budget; "
      "rerun the same command to resume after a kill");
  b->add_option("--source", a.o.source, "Head folder (ICT FaceKit layout, e.g. from `facesr head identity`) or 'procedural'")
      ->required();
  b->add_option("-o,--out", a.o.out_dir, "Output folder (the package)")->required();
  b->add_option("--budget", a.budget, "Wall-clock budget of the whole pipeline: 3h (default), 90m, 600s");
  b->add_option("--init-from", a.o.init_from,
                "A trained model, of this or another rig (e.g. samples/assets/ict.fsm): transferred to the new rig "
                "and fine-tuned instead of training from scratch");
  b->add_option("--preset", a.o.preset, "Rig build preset: default or coarse (tests, demos)");
  b->add_option("--max-frames", a.o.max_frames, "At most this many frames per performance (tiny runs; 0: all)");
  b->add_option("--max-epochs", a.o.max_epochs, "Cap on each training stage's epochs (default 1000; the budget stops it first)");
  b->add_option("--validation-every", a.o.validation_every, "Every n-th training frame held out for the choices");
  b->add_option("--device", a.o.device, "Training device: cpu, cuda or auto");
  b->add_flag("--restart", a.o.restart, "Discard the folder's finished stages and start over");
  b->add_flag("-q,--quiet", a.quiet, "No progress output");
  b->add_flag("--json", a.json,
              "Print a JSON summary: ours_mean_cm, embedded_mean_cm, ours_over_embedded, frames_ours_beats_embedded, "
              "test_frames, zero_shot (with --init-from), stages (settings, seconds, results), stages_s, machine");
  add_action(b, [] {
    a.o.budget_s = parse_duration_s(a.budget);
    a.o.progress = !a.quiet;
    const auto s = build_character(a.o);
    if (a.json) {
      std::printf("%s\n", s.dump(2).c_str());
    } else {
      std::printf("%s: ours %.4f cm, embedded %.4f cm (ratio %.3f) on %d test frames; %.0f s in all\n",
                  a.o.out_dir.c_str(), s["ours_mean_cm"].get<double>(), s["embedded_mean_cm"].get<double>(),
                  s["ours_over_embedded"].get<double>(), s["test_frames"].get<int>(), s["stages_s"].get<double>());
    }
  });
}

}  // namespace facesr::cli
