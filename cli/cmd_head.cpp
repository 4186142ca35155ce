// `facesr head identity`: new heads from the ICT identity model, for
// robustness runs and as a studio's stand-in for its own scans.
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "arg_lists.h"
#include "commands.h"
#include "core/error.h"
#include "rig/identity_head.h"

namespace facesr::cli {

void register_head(CLI::App& app) {
  auto* head = app.add_subcommand("head", "Make heads in the ICT FaceKit layout");
  head->require_subcommand(1);
  struct Args {
    IdentityHeadSpec spec;
    std::string weights, out;
    int seed = -1, modes = -1;
    double max_sigma = 3;
    bool json = false;
  };
  static Args a;
  auto* id = head->add_subcommand("identity",
                                  "A head from the identity modes: generic + Σ w_k·(identity_k − generic), "
                                  "each expression = new neutral + the generic expression delta");
  id->add_option("--ict", a.spec.ict_dir, "Generic ICT FaceKit folder")->required();
  id->add_option("--identities", a.spec.identities_dir, "Folder of identity000.obj … (one σ each)")->required();
  id->add_option("--weights", a.weights, "Comma-separated weights in σ, mode 0 first");
  id->add_option("--seed", a.seed, "Draw the weights uniformly in ±--max-sigma from this seed");
  id->add_option("--max-sigma", a.max_sigma, "Largest |weight| drawn with --seed (σ)");
  id->add_option("--modes", a.modes, "Modes drawn with --seed (default: all in --identities)");
  id->add_option("--out,-o", a.out, "Output folder")->required();
  id->add_flag("--json", a.json, "Print a JSON summary");
  add_action(id, [] {
    require(a.weights.empty() != (a.seed < 0), "give exactly one of --weights and --seed");
    if (a.seed >= 0) {
      const int available = count_identity_modes(a.spec.identities_dir);
      require(available > 0, "'" + a.spec.identities_dir + "' has no identity000.obj");
      const int modes = a.modes < 0 ? available : a.modes;
      require(modes <= available, "--modes " + std::to_string(modes) + ": only " + std::to_string(available) + " modes");
      require(a.max_sigma >= 0, "--max-sigma must be ≥ 0");
      a.spec.weights = random_identity_weights(uint32_t(a.seed), modes, a.max_sigma);
    } else {
      a.spec.weights = double_list(a.weights, "--weights");
    }
    const IdentityHeadReport r = write_identity_head(a.spec, a.out);
    nlohmann::json j = {{"out", a.out}, {"weights_sigma", a.spec.weights}, {"modes", r.modes},
                        {"expressions", r.expressions}, {"vertices", r.vertices},
                        {"max_offset_cm", r.max_offset_cm}, {"units", "cm"}};
    if (a.seed >= 0) j["seed"] = a.seed;
    if (a.json)
      std::printf("%s\n", j.dump(2).c_str());
    else
      std::printf("head '%s': %d modes, %d expressions, neutral moved by at most %.2f cm\n", a.out.c_str(), r.modes,
                  r.expressions, r.max_offset_cm);
  });
}

}  // namespace facesr::cli
