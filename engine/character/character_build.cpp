#include "character/character_build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "bench/bench_report.h"
#include "character/character_recipe.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "dataset/dataset_io.h"
#include "dataset/generate.h"
#include "perf/performance.h"
#include "render/sequence_gltf.h"
#include "rig/ict_head.h"
#include "rig/rig_build.h"
#include "rig/rig_io.h"
#include "rig/rig_preset.h"
#include "render/rig_preview.h"
#include "postfit/fit_rest_correctives.h"
#include "runtime/sr_inference.h"
#include "sr/model_transfer.h"
#include "sr/sr_model.h"
#include "train/model_evaluation.h"
#include "train/trainer.h"

namespace facesr {

namespace fs = std::filesystem;
using nlohmann::json;

SrArchitecture character_architecture() {
  SrArchitecture a;
  a.embedded_skip = true;
  return a;
}

namespace {

const char* const kStages[] = {"rig", "test_data", "train_data", "train_a", "train_b", "post_fit", "evaluate",
                               "package"};
constexpr int kStageCount = 8;

// What must match for a rerun to reuse a folder's stages.
json settings_json(const CharacterOptions& o) {
  return {{"source", o.source == "procedural" ? o.source : fs::weakly_canonical(o.source).string()},
          {"budget_s", o.budget_s},
          {"init_from", o.init_from.empty() ? "" : fs::weakly_canonical(o.init_from).string()},
          {"preset", o.preset},
          {"max_frames", o.max_frames},
          {"max_epochs", o.max_epochs},
          {"validation_every", o.validation_every},
          {"seed", o.seed},
          {"architecture", o.init_from.empty() ? architecture_to_json(character_architecture()) : json("init_from")}};
}

class Manifest {
 public:
  Manifest(std::string path, json settings) : path_(std::move(path)) {
    if (fs::exists(path_)) {
      std::ifstream in(path_);
      try {
        j_ = json::parse(in);
      } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
        throw Error(path_ + ": not valid JSON (" + e.what() + "); remove it or pass --restart");
      }
      require(j_.value("format", "") == "facesr-character", path_ + ": not a character build manifest");
      require(j_.value("settings", json()) == settings,
              path_ + ": the folder holds a build with other settings (" + j_.value("settings", json()).dump() +
                  "); use another output folder or pass --restart");
    } else {
      j_ = {{"format", "facesr-character"}, {"version", 1}, {"units", "cm"}, {"settings", settings},
            {"stages", json::object()}};
    }
  }
  bool done(const std::string& stage) const { return j_["stages"].contains(stage); }
  const json& stage(const std::string& s) const { return j_["stages"].at(s); }
  void finish(const std::string& stage, json record) {
    j_["stages"][stage] = std::move(record);
    save();
  }
  json& root() { return j_; }
  void save() {
    write_file_atomically(path_, [&](std::ostream& o) { o << j_.dump(2) << "\n"; });
  }

 private:
  std::string path_;
  json j_;
};

// One line per stage with the ETA of the whole pipeline: each stage not yet
// done is planned at its budget share; a done stage counts as its time.
class PipelineProgress {
 public:
  PipelineProgress(const CharacterBudget& b, bool enabled) : enabled_(enabled), t0_(std::chrono::steady_clock::now()) {
    planned_ = {0.02 * b.finish_s, 0.15 * b.dataset_s, 0.85 * b.dataset_s, b.train_a_s, b.train_b_s,
                0.5 * b.finish_s, 0.3 * b.finish_s, 0.18 * b.finish_s};
  }
  void begin(int k, const std::string& detail) {
    if (!enabled_) return;
    double eta = 0;
    for (int i = k; i < kStageCount; ++i) eta += planned_[size_t(i)];
    std::fprintf(stderr, "[character] stage %d/%d %s: %s (elapsed %.0f s, pipeline ETA %.0f s)\n", k + 1, kStageCount,
                 kStages[k], detail.c_str(), seconds_since(t0_), eta);
  }
  void skip(int k) {
    if (enabled_) std::fprintf(stderr, "[character] stage %d/%d %s: done earlier, kept\n", k + 1, kStageCount, kStages[k]);
  }

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point t0_;
  std::vector<double> planned_;
};

double mean_hr_step_s(const std::string& dataset_dir, const std::vector<std::string>& names) {
  double sum = 0;
  long n = 0;
  for (const auto& name : names) {
    const DatasetSequence s = read_dataset_sequence(dataset_dir + "/" + name + ".fsd");
    for (const auto& f : s.frames) sum += f.stats.hr_step_s, ++n;
  }
  require(n > 0 && sum > 0, "character build: the test split in " + dataset_dir + " has no timed HR frames");
  return sum / double(n);
}

// The validation (or test) errors of one model file.
json evaluate_file(const Rig& rig, const std::string& dataset, const std::string& model, const std::string& split,
                   int validation_every, const std::string& out_dir, bool progress) {
  ModelEvaluationOptions e;
  e.dataset_dir = dataset;
  e.model_path = model;
  e.methods = split == "test" ? std::vector<std::string>{"ours", "embedded", "blendshape"}
                              : std::vector<std::string>{"ours", "embedded"};
  e.split = split;
  e.validation_every = validation_every;
  e.out_dir = out_dir;
  e.pictures = split == "test" ? 4 : 0;
  e.spectral_k = split == "test" ? 100 : 0;
  e.penetration = split == "test";
  e.progress = progress;
  return evaluate_models(rig, e);
}

double ours_mean(const json& report) { return report.at("ours").at("mean_cm").get<double>(); }

}  // namespace

json build_character(const CharacterOptions& opt) {
  require(!opt.source.empty(), "character build: no --source head");
  require(!opt.out_dir.empty(), "character build: no output folder");
  require(std::isfinite(opt.budget_s) && opt.budget_s > 0, "character build: --budget must be positive");
  require(opt.max_frames >= 0 && opt.max_epochs >= 1, "character build: --max-frames >= 0 and --max-epochs >= 1");
  require(opt.validation_every >= 2, "character build: --validation-every must be at least 2 (the post-fit choices "
                                     "and the exported weights are chosen on those held-out frames)");
  require(opt.max_frames == 0 || opt.max_frames >= opt.validation_every,
          "character build: --max-frames " + std::to_string(opt.max_frames) + " leaves no validation frame (every " +
              std::to_string(opt.validation_every) + "-th training frame); lower --validation-every");
  const CharacterBudget budget = split_budget(opt.budget_s);
  // Everything that can be refused is checked before any long work.
  RigBuildOptions rb;
  rb.source = opt.source;
  rb.verbose = false;
  apply_rig_preset(rb, opt.preset);
  std::shared_ptr<SrModel> init;
  if (!opt.init_from.empty()) {
    init = std::make_shared<SrModel>(load_sr_model(opt.init_from));
    require(init->arch.kind == "sr" && init->arch.coordinate_upsampling && init->arch.embedded_skip,
            "character build: --init-from " + opt.init_from +
                " must be the super-resolution network with coordinate-based upsampling and the embedded skip");
  }
  if (opt.restart) fs::remove_all(opt.out_dir);
  const std::string dir = opt.out_dir, rig_path = dir + "/rig.rig", data = dir + "/dataset";
  Manifest man(dir + "/character.json", settings_json(opt));
  // Missing shapes or other vertex counts: refused before anything is written.
  if (!man.done("rig") && opt.source != "procedural") load_ict_head(opt.source, false);
  fs::create_directories(opt.out_dir);
  man.root()["machine"] = machine_description();
  man.root()["budget"] = budget.to_json();
  PipelineProgress progress(budget, opt.progress);
  const auto t_run = std::chrono::steady_clock::now();

  // rig
  if (!man.done("rig")) {
    progress.begin(0, "building the rig");
    const auto t0 = std::chrono::steady_clock::now();
    const Rig built = build_rig(rb);
    save_rig(built, rig_path);
    render_rig_preview(built, dir + "/preview.png");
    man.finish("rig", {{"seconds", seconds_since(t0)}, {"preset", opt.preset}, {"file", "rig.rig"},
                       {"lr_nodes", built.lr.mesh.X.rows()}, {"surface_vertices", built.surface.rows()}});
  } else {
    progress.skip(0);
  }
  const Rig rig = load_rig(rig_path);
  auto frames_of = [&](const std::string& name) {
    const int f = builtin_performance(name, rig.blendshape_names).frames();
    return opt.max_frames > 0 ? std::min(f, opt.max_frames) : f;
  };
  DatasetOptions dopt;
  dopt.test_names = character_test_performances();
  dopt.max_frames = opt.max_frames;
  dopt.progress = opt.progress;

  // test_data
  if (!man.done("test_data")) {
    progress.begin(1, "simulating the test split (LR and HR)");
    const auto t0 = std::chrono::steady_clock::now();
    dopt.builtins = character_test_performances();
    const DatasetSummary s = generate_dataset(rig, rig_path, data, dopt);
    require(s.diverged_frames == 0, "character build: " + std::to_string(s.diverged_frames) +
                                        " test frames diverged past recovery; see " + data);
    man.finish("test_data", {{"seconds", seconds_since(t0)}, {"performances", dopt.builtins},
                             {"hr_s_per_frame", mean_hr_step_s(data, dopt.builtins)}, {"summary", s.to_json()}});
  } else {
    progress.skip(1);
  }

  // train_data: planned once from the test split's HR cost, then kept, so a
  // resumed run simulates the same takes.
  if (!man.done("train_data")) {
    json plan = man.root().value("train_data_plan", json());
    if (plan.is_null()) {
      // The test split's wall time per frame (LR, HR, writing), or its HR
      // time with a margin where that is larger (a resumed test split has
      // no honest wall time).
      const json& t = man.stage("test_data");
      int test_frames = 0;
      for (const auto& n : character_test_performances()) test_frames += frames_of(n);
      const double per_frame = std::max(1.15 * t.at("hr_s_per_frame").get<double>(),
                                        t.at("seconds").get<double>() / std::max(1, test_frames));
      const double left = std::max(0.0, budget.dataset_s - t.at("seconds").get<double>());
      plan = plan_training_performances(left, per_frame, frames_of);
      man.root()["train_data_s_per_frame"] = per_frame;
      man.root()["train_data_plan"] = plan;
      man.save();
    }
    int planned_frames = 0;
    for (const auto& n : plan) planned_frames += frames_of(n.get<std::string>());
    progress.begin(2, "simulating " + std::to_string(plan.size()) + " training takes (" +
                          std::to_string(planned_frames) + " frames)");
    const auto t0 = std::chrono::steady_clock::now();
    dopt.builtins = character_test_performances();
    for (const auto& n : plan) dopt.builtins.push_back(n.get<std::string>());
    const DatasetSummary s = generate_dataset(rig, rig_path, data, dopt);
    man.finish("train_data", {{"seconds", seconds_since(t0)}, {"performances", plan},
                              {"frames", planned_frames}, {"summary", s.to_json()}});
  } else {
    progress.skip(2);
  }

  // train_a
  // A model carried over keeps its own layer sizes; from scratch, the character architecture.
  SrArchitecture arch = init ? init->arch : character_architecture();
  TrainOptions topt;
  topt.dataset_dir = data;
  topt.validation_every = opt.validation_every;
  topt.checkpoint_every = 1;  // a kill loses at most one epoch
  topt.seed = opt.seed;
  topt.device = opt.device;
  topt.progress = opt.progress;
  if (!man.done("train_a")) {
    json rec;
    const auto t0 = std::chrono::steady_clock::now();
    topt.out_path = dir + "/train_a.fsm";
    topt.epochs = opt.max_epochs;
    topt.time_budget_s = budget.train_a_s;
    topt.learning_rate = 1e-3;  // ICT stage 1 (BENCHMARKS.md: 1e-3 beat the paper's 1e-4)
    if (init) {
      ModelTransferReport rep;
      SrModel start = *init;
      if (init->rig_checksum != rig_checksum(rig)) {
        start = transfer_sr_model(*init, rig, rig_checksum(rig), &rep, opt.init_from + " to " + rig_path);
        rec["transfer"] = rep.to_json();
      }
      start.rest_correctives = {};  // refitted in post_fit
      start.residual_smoothing = {};
      save_sr_model(dir + "/init.fsm", start);
      topt.init_from = dir + "/init.fsm";
      topt.learning_rate = 5e-4;  // fine-tuning: the ICT fine-tunes used 3e-4 to 5e-4
      arch.zero_rest = start.arch.zero_rest;
      // Zero-shot: the transferred model before any training on this face,
      // measured for the report only (nothing is chosen on the test split).
      const json zv = evaluate_file(rig, data, dir + "/init.fsm", "validation", opt.validation_every,
                                    dir + "/eval_zero_shot", false);
      const json zt = evaluate_file(rig, data, dir + "/init.fsm", "test", opt.validation_every,
                                    dir + "/eval_zero_shot", false);
      rec["zero_shot"] = {{"validation_cm", ours_mean(zv)},
                          {"test_cm", ours_mean(zt)},
                          {"test_embedded_cm", zt.at("embedded").at("mean_cm")},
                          {"test_frames_beating_embedded", zt.value("frames_ours_beats_embedded", -1)}};
      fs::remove_all(dir + "/eval_zero_shot");
    }
    progress.begin(3, std::string(init ? "fine-tuning the transferred model" : "training") + " for up to " +
                          std::to_string(int(budget.train_a_s)) + " s");
    const TrainSummary s = train_model(rig, arch, topt);
    rec["seconds"] = seconds_since(t0);
    rec["summary"] = s.to_json();
    rec["learning_rate"] = topt.learning_rate;
    man.finish("train_a", rec);
  } else {
    progress.skip(3);
  }

  // train_b: as many epochs as its budget holds at train_a's epoch time,
  // the rate annealed to 1e-5, zero_rest in training (ICT stages 4–6).
  if (!man.done("train_b")) {
    const json& a = man.stage("train_a").at("summary");
    const double epoch_s = std::max(1e-3, a.value("mean_epoch_s", 0.0));
    const int epochs = std::clamp(int(budget.train_b_s / epoch_s), 1, opt.max_epochs);
    const SrModel am = load_sr_model(dir + "/train_a.fsm");
    double beta = topt.beta_start;
    if (am.training.contains("history") && !am.training["history"].empty())
      beta = am.training["history"].back().value("beta", beta);
    progress.begin(4, "annealed fine-tune with zero_rest, " + std::to_string(epochs) + " epochs");
    const auto t0 = std::chrono::steady_clock::now();
    arch.zero_rest = true;
    topt.out_path = dir + "/train_b.fsm";
    topt.init_from = dir + "/train_a.fsm";
    topt.epochs = epochs;
    topt.learning_rate = 3e-4;
    topt.learning_rate_final = 1e-5;
    topt.beta_start = beta;  // continue train_a's feature-norm ramp
    topt.beta_end = 20;
    topt.time_budget_s = 1.25 * budget.train_b_s;
    const TrainSummary s = train_model(rig, arch, topt);
    man.finish("train_b", {{"seconds", seconds_since(t0)}, {"epochs", epochs}, {"beta_start", beta},
                           {"summary", s.to_json()}});
  } else {
    progress.skip(4);
  }

  // post_fit: each step kept only if the validation error falls (the rule of
  // ICT stages 8 and 9; the test split is never looked at here).
  if (!man.done("post_fit")) {
    progress.begin(5, "choosing residual smoothing and near-rest correctives on validation frames");
    const auto t0 = std::chrono::steady_clock::now();
    const std::string scratch = dir + "/post_fit";
    fs::create_directories(scratch);
    json rec = {{"smoothing", json::array()}};
    SrModel best = load_sr_model(dir + "/train_b.fsm");
    double best_val = ours_mean(evaluate_file(rig, data, dir + "/train_b.fsm", "validation", opt.validation_every,
                                              scratch + "/eval", false));
    rec["smoothing"].push_back({{"iterations", 0}, {"validation_cm", best_val}});
    for (int k : {1, 2, 4}) {
      SrModel m = best;
      m.residual_smoothing = {0.5, k};
      const std::string f = scratch + "/smooth" + std::to_string(k) + ".fsm";
      save_sr_model(f, m);
      const double v = ours_mean(evaluate_file(rig, data, f, "validation", opt.validation_every, scratch + "/eval", false));
      rec["smoothing"].push_back({{"iterations", k}, {"validation_cm", v}});
      if (v < best_val) best_val = v, best.residual_smoothing = m.residual_smoothing;
    }
    rec["smoothing_chosen"] = best.residual_smoothing.iterations;
    try {
      RestCorrectiveFitOptions c;
      c.validation_every = opt.validation_every;
      SrModel m = best;
      RestCorrectiveFit fit = fit_rest_correctives(m, data, c);
      m.rest_correctives = std::move(fit.correctives);
      const std::string f = scratch + "/correctives.fsm";
      save_sr_model(f, m);
      const double v = ours_mean(evaluate_file(rig, data, f, "validation", opt.validation_every, scratch + "/eval", false));
      rec["correctives"] = {{"shapes", m.rest_correctives.count()}, {"validation_cm", v}, {"kept", v <= best_val}};
      if (v <= best_val) best_val = v, best = std::move(m);
    } catch (const Error& e) {
      rec["correctives"] = {{"kept", false}, {"skipped", e.what()}};
    }
    rec["validation_cm"] = best_val;
    best.training["character_post_fit"] = rec;
    save_sr_model(dir + "/model.fsm", best);
    fs::remove_all(scratch);
    rec["seconds"] = seconds_since(t0);
    man.finish("post_fit", rec);
  } else {
    progress.skip(5);
  }

  // evaluate
  if (!man.done("evaluate")) {
    progress.begin(6, "ours and embedded on the test split");
    const auto t0 = std::chrono::steady_clock::now();
    const json r = evaluate_file(rig, data, dir + "/model.fsm", "test", opt.validation_every, dir + "/eval", opt.progress);
    const double ours = ours_mean(r), emb = r.at("embedded").at("mean_cm").get<double>();
    man.finish("evaluate", {{"seconds", seconds_since(t0)},
                            {"ours_mean_cm", ours},
                            {"embedded_mean_cm", emb},
                            {"ours_over_embedded", emb > 0 ? ours / emb : 0},
                            {"blendshape_mean_cm", r.at("blendshape").at("mean_cm")},
                            {"frames_ours_beats_embedded", r.value("frames_ours_beats_embedded", -1)},
                            {"test_frames", r.value("test_frames", 0)},
                            {"report", "eval/report.json"}});
  } else {
    progress.skip(6);
  }

  // package: the runtime's own inference (no LibTorch) on the first test
  // take, as a glTF a studio can open.
  if (!man.done("package")) {
    progress.begin(7, "glTF of a test take through the runtime inference");
    const auto t0 = std::chrono::steady_clock::now();
    const auto model = std::make_shared<const SrModel>(load_sr_model(dir + "/model.fsm"));
    require_model_matches_rig(*model, rig_checksum(rig), int(rig.lr.mesh.X.rows()), int(rig.surface.rows()),
                              dir + "/model.fsm", rig_path);
    auto inf = make_cpu_inference(model);
    const std::string take = character_test_performances().front();
    const DatasetSequence ds = read_dataset_sequence(data + "/" + take + ".fsd");
    Sequence seq;
    seq.header.resolution = "high";
    seq.header.rig_checksum = rig_checksum(rig);
    seq.header.fps = ds.header.fps;
    seq.header.num_nodes = 0;
    seq.header.num_surface = uint64_t(rig.surface.rows());
    const int M = int(rig.surface.rows());
    std::vector<float> out(size_t(3 * M));
    const int frames = std::min(ds.num_frames(), kMaxGltfFrames);
    for (int f = 0; f < frames; ++f) {
      inf->infer(ds.frame(f).lr_disp.data(), out.data());
      seq.time.push_back(ds.frame(f).time);
      for (int v = 0; v < M; ++v)
        for (int c = 0; c < 3; ++c) seq.surface.push_back(float(rig.surface(v, c)) + out[size_t(3 * v + c)]);
    }
    seq.header.num_frames = uint64_t(frames);
    write_sequence_gltf(rig, seq, dir + "/" + take + ".gltf");
    for (const char* f : {"train_a.fsm", "train_b.fsm", "init.fsm"}) fs::remove(dir + "/" + f);
    man.finish("package", {{"seconds", seconds_since(t0)},
                           {"files", {"rig.rig", "model.fsm", "preview.png", take + ".gltf", "eval/report.json",
                                      "character.json"}},
                           {"gltf_frames", frames}});
  } else {
    progress.skip(7);
  }

  json summary = {{"out", dir}, {"units", "cm"}, {"machine", machine_description()},
                  {"this_run_s", seconds_since(t_run)}, {"budget_s", opt.budget_s}};
  double total = 0;
  for (const char* s : kStages) total += man.stage(s).value("seconds", 0.0);
  summary["stages_s"] = total;
  summary["stages"] = man.root()["stages"];
  for (const char* k : {"ours_mean_cm", "embedded_mean_cm", "ours_over_embedded", "frames_ours_beats_embedded",
                        "test_frames"})
    summary[k] = man.stage("evaluate").at(k);
  // Absent from packages evaluated before the blendshape baseline existed.
  if (man.stage("evaluate").contains("blendshape_mean_cm"))
    summary["blendshape_mean_cm"] = man.stage("evaluate")["blendshape_mean_cm"];
  if (man.stage("train_a").contains("zero_shot")) summary["zero_shot"] = man.stage("train_a")["zero_shot"];
  man.root()["summary"] = {{"stages_s", total}, {"ours_over_embedded", summary["ours_over_embedded"]}};
  man.save();
  return summary;
}

}  // namespace facesr
