#include "commands.h"

#include <map>

namespace facesr::cli {
namespace {
std::map<const CLI::App*, std::function<void()>>& actions() {
  static std::map<const CLI::App*, std::function<void()>> a;
  return a;
}
void run_in(CLI::App* app) {
  for (CLI::App* sub : app->get_subcommands()) {
    auto it = actions().find(sub);
    if (it != actions().end()) {
      it->second();
      return;
    }
    run_in(sub);
  }
}
}  // namespace

void add_action(CLI::App* sub, std::function<void()> action) { actions()[sub] = std::move(action); }
void run_selected(CLI::App& app) { run_in(&app); }

}  // namespace facesr::cli
