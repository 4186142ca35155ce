// facesr eval: the network against the baselines on a dataset's test split
// (engine/train/model_evaluation.h).
#include <cstdio>

#include "bench/bench_report.h"
#include "arg_lists.h"
#include "commands.h"
#include "core/error.h"
#include "rig/rig_io.h"
#include "train/model_evaluation.h"

namespace facesr::cli {

void register_eval(CLI::App& app) {
  struct Args {
    std::string rig, methods = "ours,embedded,blendshape,rbf,mls,vae", markdown, tag;
    ModelEvaluationOptions o;
    bool json = false, quiet = false;
  };
  static Args a;
  auto* sub = app.add_subcommand("eval", "Compare the network with the embedded, RBF, MLS and β-VAE baselines");
  sub->add_option("--rig", a.rig, "Rig file")->required();
  sub->add_option("--dataset", a.o.dataset_dir, "Dataset folder (its test split is evaluated)")->required();
  sub->add_option("--split", a.o.split,
                  "test (default) | validation: the training frames `facesr train` held out (every n-th, "
                  "--validation-every), for choosing between models without looking at the test split");
  sub->add_option("--validation-every", a.o.validation_every,
                  "With --split validation: the n that training used (default 10, train's default)");
  sub->add_option("--model", a.o.model_path, "Trained network (.fsm from `facesr train`)");
  sub->add_option("--vae", a.o.vae_path, "Trained β-VAE (.fsm from `facesr train --kind vae`)");
  sub->add_option("--methods", a.methods, "Comma-separated methods (default ours,embedded,blendshape,rbf,mls,vae; blendshape: the linear blendshape surface at each frame's weights)");
  sub->add_option("--out,-o", a.o.out_dir, "Output folder: frame_errors.csv/.svg, pictures/, report.json")->required();
  sub->add_option("--pictures", a.o.pictures, "Test frames pictured as error heat maps (default 4)");
  sub->add_option("--spectral-k", a.o.spectral_k, "Eigenvectors in the low band (default 100)");
  sub->add_option("--rbf-sigma", a.o.rbf_sigma_cm, "RBF width in cm (default: fitted on training frames)");
  sub->add_option("--rbf-mu", a.o.rbf_regularization, "RBF regularisation (default: fitted)");
  sub->add_option("--mls-sigma", a.o.mls_sigma_cm, "MLS width in cm (default: fitted on training frames)");
  sub->add_option("--fit-frames", a.o.fit_frames, "Training frames used to fit the baselines' widths (default 24)");
  sub->add_option("--markdown", a.markdown, "Record the table in this Markdown file (e.g. BENCHMARKS.md)");
  sub->add_option("--markdown-tag", a.tag, "Section name in that file (default eval-<rig>, or eval-<rig>-validation)");
  sub->add_flag("--json", a.json,
                "Print the report: per method mean_cm, median_cm, std_cm, max_cm, min_cm, dame, normal_deg; "
                "frames_ours_beats_embedded, test_frames (the frames evaluated, of --split), split");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  add_action(sub, [] {
    require(a.o.pictures >= 0 && a.o.pictures <= 64, "--pictures must be in [0, 64]");
    require(a.o.fit_frames >= 1, "--fit-frames must be at least 1");
    a.o.methods = split_list(a.methods);
    a.o.progress = !a.quiet;
    const Rig rig = load_rig(a.rig);
    std::string md;
    nlohmann::json j = evaluate_models(rig, a.o, &md);
    j["machine"] = machine_description();
    j["date"] = today_iso();
    if (!a.markdown.empty()) {
      const std::string head = "Measured " + today_iso() + " on " + machine_description() + ". Rig `" + rig.name +
                               "`, dataset `" + a.o.dataset_dir + "`, " + std::to_string(j.value("test_frames", 0)) +
                               " " + a.o.split + " frames.\n\n";
      // Validation numbers get their own section, so they never replace the test table.
      const std::string tag = !a.tag.empty()              ? a.tag
                              : a.o.split == "validation" ? "eval-" + rig.name + "-validation"
                                                          : "eval-" + rig.name;
      update_markdown_section(a.markdown, tag, head + md);
    }
    if (a.json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      for (const auto& m : j["eval"]["methods"])
        std::printf("%-9s mean %.4f cm, max %.4f cm, DAME %.4f, normal %.2f deg\n", m.get<std::string>().c_str(),
                    j[m.get<std::string>()]["mean_cm"].get<double>(), j[m.get<std::string>()]["max_cm"].get<double>(),
                    j[m.get<std::string>()]["dame"].get<double>(), j[m.get<std::string>()]["normal_deg"].get<double>());
      if (j.contains("frames_ours_beats_embedded"))
        std::printf("ours beats embedded on %d of %d %s frames\n", j["frames_ours_beats_embedded"].get<int>(),
                    j["test_frames"].get<int>(), a.o.split.c_str());
      std::printf("wrote %s\n", a.o.out_dir.c_str());
    }
  });
}

}  // namespace facesr::cli
