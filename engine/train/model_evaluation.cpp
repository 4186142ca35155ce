#include "train/model_evaluation.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "baselines/blendshape.h"
#include "baselines/fit_sigma.h"
#include "baselines/mls.h"
#include "baselines/rbf.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "eval/evaluate.h"
#include "eval/lip_penetration.h"
#include "rig/rig_io.h"
#include "sr/sr_model.h"
#include "train/torch_predictor.h"
#include "train/training_data.h"

namespace facesr {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::vector<std::vector<float>> frames_of(const torch::Tensor& t) {
  const auto c = t.contiguous();
  std::vector<std::vector<float>> out(size_t(c.size(0)));
  const int64_t n = c.size(1) * c.size(2);
  for (int64_t f = 0; f < c.size(0); ++f) out[size_t(f)].assign(c[f].data_ptr<float>(), c[f].data_ptr<float>() + n);
  return out;
}

bool wanted(const ModelEvaluationOptions& o, const std::string& m) {
  return std::find(o.methods.begin(), o.methods.end(), m) != o.methods.end();
}

// Up to `count` training frames, evenly spaced, for fitting σ.
std::vector<int64_t> fit_subset(int64_t F, int count) {
  std::vector<int64_t> idx;
  const int64_t n = std::min<int64_t>(F, std::max(1, count));
  for (int64_t i = 0; i < n; ++i) idx.push_back(i * F / n);
  return idx;
}

// Per method (and the HR reference, "hr"): the deepest lip–lip and lip–teeth
// penetration over the frames, the mean of the per-frame deepest, and the
// frames above 0.05 cm (cm).
json penetration_report(const Rig& rig, const std::vector<EvalFrame>& frames, const std::vector<EvalMethod>& methods,
                        const std::vector<std::array<float, 12>>& jaw, std::string* markdown) {
  LipPenetrationSetup setup;
  try {
    setup = lip_penetration_setup(rig);
  } catch (const Error& e) {
    return {{"skipped", std::string("the rig's lips could not be found: ") + e.what()}};
  }
  json out = {{"units", "cm"}, {"threshold_cm", 0.05}, {"upper_lip_vertices", setup.upper.size()},
              {"lower_lip_vertices", setup.lower.size()}};
  std::string md = "\n| surface | lip–lip max (cm) | lip–lip mean (cm) | frames > 0.05 cm | lip–teeth max (cm) | "
                   "lip–teeth mean (cm) | frames > 0.05 cm |\n|---|---|---|---|---|---|---|\n";
  auto measure = [&](const std::string& name, const std::function<const std::vector<float>&(size_t)>& disp) {
    double lmax = 0, lsum = 0, tmax = 0, tsum = 0;
    int lover = 0, tover = 0;
    Points X = rig.surface;
    for (size_t f = 0; f < frames.size(); ++f) {
      const std::vector<float>& d = disp(f);
      for (long v = 0; v < X.rows(); ++v)
        for (int c = 0; c < 3; ++c) X(v, c) = rig.surface(v, c) + double(d[size_t(3 * v + c)]);
      const LipPenetration p = lip_penetration(setup, X, jaw[f]);
      lmax = std::max(lmax, p.lip_cm), lsum += p.lip_cm, lover += p.lip_cm > 0.05;
      tmax = std::max(tmax, p.teeth_cm), tsum += p.teeth_cm, tover += p.teeth_cm > 0.05;
    }
    const double n = std::max<size_t>(1, frames.size());
    out[name] = {{"lip_max_cm", lmax}, {"lip_mean_cm", lsum / n}, {"lip_frames_over", lover},
                 {"teeth_max_cm", tmax}, {"teeth_mean_cm", tsum / n}, {"teeth_frames_over", tover}};
    char row[256];
    std::snprintf(row, sizeof row, "| %s | %.3f | %.4f | %d | %.3f | %.4f | %d |\n", name.c_str(), lmax, lsum / n, lover,
                  tmax, tsum / n, tover);
    md += row;
  };
  measure("hr", [&](size_t f) -> const std::vector<float>& { return frames[f].reference_disp; });
  for (const auto& m : methods)
    measure(m.name, [&](size_t f) -> const std::vector<float>& { return m.predicted_disp[f]; });
  if (markdown)
    *markdown = md + "\nLip contact on each surface (eval/lip_penetration.h): deepest lip vertex behind the other "
                     "lip and inside a tooth, vertices already in contact at rest not counted.\n";
  return out;
}

}  // namespace

json evaluate_models(const Rig& rig, const ModelEvaluationOptions& opt, std::string* markdown) {
  for (const auto& m : opt.methods)
    require(m == "ours" || m == "embedded" || m == "blendshape" || m == "rbf" || m == "mls" || m == "vae",
            "eval: unknown method '" + m + "' (expected ours, embedded, blendshape, rbf, mls, vae)");
  require(!opt.out_dir.empty(), "eval: no output folder");
  const uint64_t checksum = rig_checksum(rig);
  // Only the RBF and MLS baselines fit their widths on training frames.
  const bool fits = wanted(opt, "rbf") || wanted(opt, "mls");
  require(opt.split == "test" || opt.split == "validation",
          "eval: split must be test or validation, not '" + opt.split + "'");
  const bool on_validation = opt.split == "validation";
  require(!on_validation || opt.validation_every >= 2,
          "eval: --validation-every must be at least 2 (every n-th training frame is evaluated)");
  const DatasetSplit data =
      load_dataset_split(opt.dataset_dir, checksum, on_validation ? opt.validation_every : 0, fits || on_validation);
  const FrameSet& evaluated = on_validation ? data.validation : data.test;
  require(evaluated.size() > 0, on_validation ? opt.dataset_dir + ": no validation frames (training sequences shorter "
                                                                  "than --validation-every " +
                                                    std::to_string(opt.validation_every) + ")"
                                              : opt.dataset_dir + ": no test frames (no sequence has split \"test\")");

  // Load every model before computing anything, so a wrong file fails fast.
  std::unique_ptr<SrModel> ours, vae;
  if (wanted(opt, "ours")) {
    require(!opt.model_path.empty(), "eval: method 'ours' needs --model");
    ours = std::make_unique<SrModel>(load_sr_model(opt.model_path));
    require(ours->arch.kind == "sr", opt.model_path + ": is a '" + ours->arch.kind + "' model, not the network");
    require_model_matches_rig(*ours, checksum, data.num_lr, data.num_hr, opt.model_path, "rig '" + rig.name + "'");
  }
  if (wanted(opt, "vae") && !opt.vae_path.empty()) {
    vae = std::make_unique<SrModel>(load_sr_model(opt.vae_path));
    require(vae->arch.kind == "vae", opt.vae_path + ": is a '" + vae->arch.kind + "' model, not a β-VAE");
    require_model_matches_rig(*vae, checksum, data.num_lr, data.num_hr, opt.vae_path, "rig '" + rig.name + "'");
  }
  fs::create_directories(opt.out_dir);

  std::vector<EvalFrame> frames;
  const auto hr = frames_of(evaluated.hr);
  for (size_t f = 0; f < hr.size(); ++f) frames.push_back({evaluated.sequence[f], evaluated.frame[f], hr[f]});
  std::vector<EvalMethod> methods;
  json timing = json::object(), baselines = json::object();
  const int64_t T = evaluated.size();
  auto timed = [&](const std::string& name, const std::function<std::vector<std::vector<float>>()>& run) {
    if (opt.progress)
      std::fprintf(stderr, "[eval] %s on %lld %s frames ...\n", name.c_str(), (long long)T, opt.split.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    methods.push_back({name, run()});
    timing[name + "_ms_per_frame"] = 1e3 * seconds_since(t0) / double(T);
  };

  if (ours) timed("ours", [&] { return frames_of(TorchPredictor(*ours).predict(evaluated.lr)); });
  if (wanted(opt, "embedded")) methods.push_back({"embedded", frames_of(evaluated.embedded)});
  if (wanted(opt, "blendshape")) {
    timed("blendshape", [&] {
      const BlendshapeBaseline b(rig, data.weight_names);
      std::vector<std::vector<float>> out(evaluated.weights.size(), std::vector<float>(size_t(3 * data.num_hr)));
      for (size_t f = 0; f < out.size(); ++f) b.apply(evaluated.weights[f], out[f].data());
      return out;
    });
  }

  if (wanted(opt, "rbf") || wanted(opt, "mls")) {
    // The baselines use the network's own neighbourhoods when it has them.
    SrGeometry g = ours && ours->arch.upsample_k == 20 ? ours->geometry : build_sr_geometry(rig);
    const auto sub = fit_subset(data.train.size(), opt.fit_frames);
    const auto lr_fit = data.train.lr.index_select(0, torch::tensor(sub)).contiguous();
    const auto hr_fit = data.train.hr.index_select(0, torch::tensor(sub)).contiguous();
    std::vector<const float*> lrp, hrp;
    for (int64_t i = 0; i < lr_fit.size(0); ++i) {
      lrp.push_back(lr_fit[i].data_ptr<float>());
      hrp.push_back(hr_fit[i].data_ptr<float>());
    }
    const double cell = rig.lattice.cell > 0 ? rig.lattice.cell : 1.0;
    const std::vector<double> sigmas{0.5 * cell, cell, 2 * cell, 4 * cell};
    const auto lr_eval = frames_of(evaluated.lr);
    auto run_baseline = [&](const auto& b) {
      std::vector<std::vector<float>> out(lr_eval.size(), std::vector<float>(size_t(3 * data.num_hr)));
      for (size_t f = 0; f < lr_eval.size(); ++f) b.apply(lr_eval[f].data(), out[f].data());
      return out;
    };
    if (wanted(opt, "rbf")) {
      RbfParams p{opt.rbf_sigma_cm, opt.rbf_regularization};
      std::vector<double> errs;
      if (p.sigma_cm <= 0 || p.regularization < 0) {
        if (opt.progress) std::fprintf(stderr, "[eval] fitting the RBF width and regularisation on %zu training frames\n", lrp.size());
        const std::vector<double> mus = p.regularization >= 0 ? std::vector<double>{p.regularization}
                                                              : std::vector<double>{0.01, 0.1, 1.0};
        const std::vector<double> sig = p.sigma_cm > 0 ? std::vector<double>{p.sigma_cm} : sigmas;
        p = fit_rbf_params(g, lrp, hrp, sig, mus, &errs);
      }
      baselines["rbf"] = {{"sigma_cm", p.sigma_cm}, {"regularization", p.regularization},
                          {"fit_frames", lrp.size()}, {"fit_errors_cm", errs}};
      const RbfBaseline rbf(g, p.sigma_cm, p.regularization);
      timed("rbf", [&] { return run_baseline(rbf); });
    }
    if (wanted(opt, "mls")) {
      double s = opt.mls_sigma_cm;
      std::vector<double> errs;
      if (s <= 0) s = fit_mls_sigma(g, lrp, hrp, sigmas, &errs);
      baselines["mls"] = {{"sigma_cm", s}, {"fit_frames", lrp.size()}, {"fit_errors_cm", errs}};
      const MlsBaseline mls(g, s);
      timed("mls", [&] { return run_baseline(mls); });
    }
  }
  if (vae) timed("vae", [&] { return frames_of(TorchPredictor(*vae).predict(evaluated.lr)); });
  require(!methods.empty(), "eval: no method to evaluate (give --model and/or --vae, or --methods embedded,...)");

  EvalOptions eo;
  eo.spectral = opt.spectral_k > 0;
  if (eo.spectral) eo.spectral_options.k = opt.spectral_k;
  if (on_validation) eo.title = "Frame-wise surface reconstruction error on the validation frames";
  eo.csv_path = opt.out_dir + "/frame_errors.csv";
  eo.svg_path = opt.out_dir + "/frame_errors.svg";
  eo.picture_dir = opt.out_dir + "/pictures";
  for (int i = 0; i < opt.pictures && T > 0; ++i) eo.picture_frames.push_back(int((2 * i + 1) * T / (2 * opt.pictures)));
  const EvalReport report = evaluate(rig, frames, methods, eo);
  json j = report.to_json();
  std::string penetration_md;
  if (opt.penetration) j["penetration"] = penetration_report(rig, frames, methods, evaluated.jaw, &penetration_md);
  j["baselines"] = baselines;
  j["timing"] = timing;
  j["dataset"] = opt.dataset_dir;
  // "test_frames" keeps its name (the agreed key) and counts the evaluated frames of this split.
  j["split"] = opt.split;
  if (on_validation) j["validation_every"] = opt.validation_every;
  if (ours) j["model"] = {{"path", opt.model_path}, {"epochs", ours->training.value("epochs", 0)},
                          {"train_time_s", ours->training.value("train_time_s", 0.0)}};
  const std::string text = j.dump(2) + "\n";
  write_file_atomically(opt.out_dir + "/report.json", [&](std::ostream& o) { o << text; });
  if (markdown) *markdown = report.to_markdown() + penetration_md;
  return j;
}

}  // namespace facesr
