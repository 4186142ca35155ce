// `facesr model`: inspect a trained model file, and set zero_rest on one
// after training (how the shipped ICT model was made: see docs/network.md).
#include <cstdio>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/error.h"
#include "sr/sr_model.h"

namespace facesr::cli {

namespace {

nlohmann::json model_summary(const SrModel& m, const std::string& path) {
  size_t parameters = 0;
  for (const auto& t : m.tensors) parameters += t.values.size();
  return {{"model", path},          {"kind", m.arch.kind},          {"rig_name", m.rig_name},
          {"num_lr", m.num_lr},     {"num_hr", m.num_hr},           {"parameters", parameters},
          {"zero_rest", m.arch.zero_rest}, {"embedded_skip", m.arch.embedded_skip}, {"units", "cm"}};
}

}  // namespace

void register_model(CLI::App& app) {
  auto* model = app.add_subcommand("model", "Inspect or adjust a trained model file (.fsm)");
  model->require_subcommand(1);

  struct InfoArgs {
    std::string path;
    bool json = false;
  };
  static InfoArgs info;
  auto* i = model->add_subcommand("info", "Print a model file's architecture and rig");
  i->add_option("model", info.path, "Model file (.fsm)")->required();
  i->add_flag("--json", info.json, "Print a JSON summary: kind, rig_name, num_lr, num_hr, parameters, zero_rest, embedded_skip");
  add_action(i, [] {
    const SrModel m = load_sr_model(info.path);
    const auto s = model_summary(m, info.path);
    if (info.json)
      std::printf("%s\n", s.dump(2).c_str());
    else
      std::printf("%s: '%s' model for rig '%s' (%d LR nodes, %d HR vertices), %zu parameters, zero_rest %s\n",
                  info.path.c_str(), m.arch.kind.c_str(), m.rig_name.c_str(), m.num_lr, m.num_hr,
                  s["parameters"].get<size_t>(), m.arch.zero_rest ? "on" : "off");
  });

  struct ZeroRestArgs {
    std::string in, out;
    bool json = false;
  };
  static ZeroRestArgs zr;
  auto* z = model->add_subcommand(
      "zero-rest",
      "Write a copy whose output at the rest input is subtracted (rest maps exactly to rest; not in the paper)");
  z->add_option("model", zr.in, "Trained model file (.fsm, kind sr)")->required();
  z->add_option("-o,--out", zr.out, "Output model file")->required();
  z->add_flag("--json", zr.json, "Print a JSON summary of the written model");
  add_action(z, [] {
    SrModel m = load_sr_model(zr.in);
    require(m.arch.kind == "sr", zr.in + ": zero-rest applies to the super-resolution network, not to a '" +
                                     m.arch.kind + "' model");
    require(!m.arch.zero_rest, zr.in + ": zero_rest is already set");
    m.arch.zero_rest = true;
    m.training["zero_rest_added_after_training"] = true;
    save_sr_model(zr.out, m);  // written to a temporary name, then renamed
    if (zr.json) std::printf("%s\n", model_summary(m, zr.out).dump(2).c_str());
  });
}

}  // namespace facesr::cli
