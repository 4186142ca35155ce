#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/error.h"

namespace facesr::cli {

void register_rig(CLI::App& app) {
  auto* rig = app.add_subcommand("rig", "Build and inspect anatomical face rigs");
  rig->require_subcommand(1);
  (void)rig;
}

}  // namespace facesr::cli
