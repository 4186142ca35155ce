// facesr command-line tool: one binary, one subcommand per job. Progress goes
// to stderr; with --json a machine-readable summary is the only stdout.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"facesr: physics-based facial animation with simulation super-resolution"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "facesr 0.1.0");
  facesr::cli::register_head(app);
  facesr::cli::register_rig(app);
  facesr::cli::register_perf(app);
  facesr::cli::register_simulate(app);
  facesr::cli::register_render(app);
  facesr::cli::register_bench(app);
  facesr::cli::register_dataset(app);
  facesr::cli::register_train(app);
  facesr::cli::register_eval(app);
  facesr::cli::register_play(app);
  facesr::cli::register_model(app);
  facesr::cli::register_character(app);
  facesr::cli::register_devices(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    facesr::cli::run_selected(app);
  } catch (const facesr::Error& e) {
    std::fprintf(stderr, "facesr: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "facesr: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
