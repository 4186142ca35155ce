#include "train/trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "rig/rig_io.h"
#include "sr/sr_geometry.h"
#include "train/model_export.h"
#include "train/lr_schedule.h"
#include "train/sr_loss.h"
#include "train/sr_network.h"
#include "train/train_device.h"
#include "train/training_data.h"
#include "train/vae_network.h"

namespace facesr {

namespace fs = std::filesystem;
using nlohmann::json;

json TrainSummary::to_json() const {
  return {{"kind", kind},
          {"device", device},
          {"epochs_planned", epochs_planned},
          {"epochs", epochs_done},
          {"resumed_from_epoch", resumed_from_epoch},
          {"best_epoch", best_epoch},
          {"train_frames", train_frames},
          {"validation_frames", validation_frames},
          {"capped_left_out", capped_left_out},
          {"parameters", parameters},
          {"first_loss", first_loss},
          {"final_loss", final_loss},
          {"first_l1_cm", first_l1_cm},
          {"final_l1_cm", final_l1_cm},
          {"best_validation_cm", best_validation_cm},
          {"train_time_s", train_time_s},
          {"mean_epoch_s", mean_epoch_s},
          {"stopped_early", stopped_early},
          {"hit_time_limit", hit_time_limit},
          {"finished", finished},
          {"units", "cm"}};
}

namespace {

// One of the two trainable models behind one interface.
struct Net {
  SrNetwork sr{nullptr};
  VaeNetwork vae{nullptr};
  torch::Tensor rest, tris;  // for the face-normal loss

  torch::nn::Module& module() { return sr ? static_cast<torch::nn::Module&>(*sr) : *vae; }
  // The loss to minimise, and (in `l1_cm`) the mean L1 error per HR vertex
  // of the batch, which stays comparable while β changes the total.
  torch::Tensor loss(const torch::Tensor& lr, const torch::Tensor& hr, const TrainOptions& o, double beta,
                     double& l1_cm, const torch::Tensor& frame_weights = {}) {
    const double BM = double(hr.size(0) * hr.size(1));
    if (sr) {
      auto out = sr->forward(lr);
      const LossTerms t = sr_loss(out.hr_disp, hr, rest, tris, out.features, o.alpha, beta, frame_weights);
      // The unweighted L1, so that progress stays comparable between runs.
      l1_cm = frame_weights.defined() ? (out.hr_disp - hr).abs().sum().item<double>() / BM
                                      : t.recon.item<double>() * double(hr.size(0)) / BM;
      return t.total;
    }
    auto out = vae->forward(lr, true);
    l1_cm = (out.hr_disp - hr).abs().sum().item<double>() / BM;
    return vae_loss(out, hr, vae->arch().output_scale, o.vae_beta) / double(hr.size(1));
  }
  torch::Tensor predict(const torch::Tensor& lr) {
    return sr ? sr->forward(lr).hr_disp : vae->forward(lr, false).hr_disp;
  }
};

double rms(const torch::Tensor& t) {
  const double v = std::sqrt(t.pow(2).mean().item<double>());
  return v > 1e-12 ? v : 1.0;
}

// Mean per-vertex Euclidean error (cm) of the model over a frame set.
double mean_error_cm(Net& net, const FrameSet& s, const torch::Device& dev, int batch) {
  torch::NoGradGuard no_grad;
  net.module().eval();
  double sum = 0;
  for (int64_t b = 0; b < s.size(); b += batch) {
    const int64_t n = std::min<int64_t>(batch, s.size() - b);
    const auto pred = net.predict(s.lr.narrow(0, b, n).to(dev));
    sum += (pred - s.hr.narrow(0, b, n).to(dev)).norm(2, 2).sum().item<double>();
  }
  net.module().train();
  return sum / double(s.size() * s.hr.size(1));
}

json config_fingerprint(const SrArchitecture& a, const TrainOptions& o) {
  json j = {{"architecture", architecture_to_json(a)}, {"batch_size", o.batch_size}, {"learning_rate", o.learning_rate},
            {"alpha", o.alpha}, {"beta_start", o.beta_start}, {"beta_end", o.beta_end}, {"vae_beta", o.vae_beta},
            {"validation_every", o.validation_every}, {"seed", o.seed},
            {"dataset", fs::weakly_canonical(o.dataset_dir).string()}};
  // Only when set, so that checkpoints from before these options still resume.
  if (o.learning_rate_final > 0) j["learning_rate_final"] = o.learning_rate_final;
  if (o.relative_floor_cm > 0) j["relative_floor_cm"] = o.relative_floor_cm;
  if (!o.init_from.empty()) j["init_from"] = fs::weakly_canonical(o.init_from).string();
  return j;
}

template <class T>
void save_archive(const std::string& path, const T& obj) {
  torch::serialize::OutputArchive ar;
  obj.save(ar);
  write_file_atomically(path, [&](std::ostream& out) { ar.save_to(out); });
}

template <class T>
void load_archive(const std::string& path, T& obj, const torch::Device& dev) {
  torch::serialize::InputArchive ar;
  ar.load_from(path, dev);
  obj.load(ar);
}

// Checkpoint layout: model-<epoch>.pt, optimizer-<epoch>.pt, best.pt, and
// state.json, written last, which names the epoch; older files are removed
// after it, so an interrupted save leaves the previous checkpoint usable.
struct Checkpoint {
  std::string dir;
  std::string state() const { return dir + "/state.json"; }
  std::string model(int e) const { return dir + "/model-" + std::to_string(e) + ".pt"; }
  std::string optim(int e) const { return dir + "/optimizer-" + std::to_string(e) + ".pt"; }
  std::string best() const { return dir + "/best.pt"; }
};

void validate(const TrainOptions& o) {
  require(o.epochs >= 1, "train: --epochs must be at least 1");
  require(o.batch_size >= 1, "train: --batch must be at least 1");
  require(o.learning_rate > 0 && std::isfinite(o.learning_rate), "train: --lr must be a positive number");
  require(o.learning_rate_final >= 0 && std::isfinite(o.learning_rate_final),
          "train: --lr-final must be a positive number (or 0: constant rate)");
  require(o.alpha >= 0 && o.beta_start >= 0 && o.beta_end >= 0 && o.vae_beta >= 0,
          "train: loss weights must be >= 0");
  require(o.checkpoint_every >= 1, "train: --checkpoint-every must be at least 1");
  require(o.validation_every >= 0 && o.validation_every != 1,
          "train: --validation-every must be 0 (none) or at least 2");
  require(o.patience >= 0, "train: --patience must be >= 0");
  require(o.relative_floor_cm >= 0 && std::isfinite(o.relative_floor_cm),
          "train: --relative-floor must be >= 0 cm (0: the paper's unweighted loss)");
  require(!o.out_path.empty(), "train: no output model path");
}

}  // namespace

TrainSummary train_model(const Rig& rig, const SrArchitecture& arch_in, const TrainOptions& opt) {
  validate(opt);
  const auto t_start = std::chrono::steady_clock::now();
  const uint64_t checksum = rig_checksum(rig);
  const DatasetSplit data = load_dataset_split(opt.dataset_dir, checksum, opt.validation_every, true, opt.keep_capped);
  require(data.num_hr == rig.num_surface_vertices(),
          opt.dataset_dir + ": the dataset has " + std::to_string(data.num_hr) + " surface vertices, the rig " +
              std::to_string(rig.num_surface_vertices()));
  use_all_cores();
  const torch::Device dev = training_device(opt.device);

  SrArchitecture arch = arch_in;
  arch.input_scale = rms(data.train.lr);
  arch.output_scale = rms(data.train.hr);
  SrModel init;
  if (!opt.init_from.empty()) {
    init = load_sr_model(opt.init_from);
    require_model_matches_rig(init, checksum, data.num_lr, data.num_hr, opt.init_from, "rig '" + rig.name + "'");
    require(init.arch.kind == arch.kind, "train: --init-from " + opt.init_from + " is a '" + init.arch.kind +
                                             "' model, not '" + arch.kind + "'");
    // The weights were fitted to these scales; keeping them keeps the function.
    arch.input_scale = init.arch.input_scale;
    arch.output_scale = init.arch.output_scale;
  }
  SrModel model;
  model.rig_name = rig.name;
  model.rig_checksum = checksum;
  model.num_lr = data.num_lr;
  model.num_hr = data.num_hr;
  if (arch.kind == "sr") {
    model.geometry = build_sr_geometry(rig, {arch.graph_k, arch.upsample_k});
    require(model.geometry.num_lr == data.num_lr, "train: the rig's LR node count differs from the dataset's");
    // A model carried over from another rig keeps the encoding each node was trained with.
    if (!opt.init_from.empty()) model.geometry.pe_rows = init.geometry.pe_rows;
  } else {
    // The VAE needs only the rest poses; the neighbourhoods stay out of its file.
    SrGeometry& g = model.geometry;
    g.num_lr = data.num_lr;
    g.num_hr = data.num_hr;
    g.graph_k = arch.graph_k;
    g.upsample_k = arch.upsample_k;
    require(rig.lr.mesh.X.rows() == data.num_lr, "train: the rig's LR node count differs from the dataset's");
    g.lr_rest.assign(rig.lr.mesh.X.data(), rig.lr.mesh.X.data() + rig.lr.mesh.X.size());
    g.hr_rest.assign(rig.surface.data(), rig.surface.data() + rig.surface.size());
  }
  set_coordinate_frame(arch, model.geometry);
  model.arch = arch;

  torch::manual_seed(opt.seed);
  Net net;
  if (arch.kind == "sr") {
    net.sr = SrNetwork(arch, model.geometry);
    net.sr->to(dev);
  } else {
    net.vae = VaeNetwork(arch, data.num_lr, data.num_hr);
    net.vae->to(dev);
  }
  {
    std::vector<float> r(rig.surface.data(), rig.surface.data() + rig.surface.size());
    net.rest = torch::from_blob(r.data(), {rig.surface.rows(), 3}, torch::kFloat32).clone().to(dev);
    std::vector<int64_t> t(rig.surface_tris.data(), rig.surface_tris.data() + rig.surface_tris.size());
    net.tris = torch::from_blob(t.data(), {rig.surface_tris.rows(), 3}, torch::kLong).clone().to(dev);
  }
  if (!opt.init_from.empty()) {
    try {
      import_parameters(init, net.module());
    } catch (const Error& e) {
      throw Error("train: --init-from " + opt.init_from + " does not fit this architecture: " + e.what());
    }
  }
  torch::optim::Adam optim(net.module().parameters(), torch::optim::AdamOptions(opt.learning_rate));

  TrainSummary sum;
  sum.kind = arch.kind;
  sum.device = dev.str();
  sum.epochs_planned = opt.epochs;
  sum.train_frames = int(data.train.size());
  sum.capped_left_out = data.capped_left_out;
  sum.validation_frames = int(data.validation.size());
  for (const auto& p : net.module().parameters()) sum.parameters += p.numel();

  // Resume.
  Checkpoint ck{opt.checkpoint_dir.empty() ? opt.out_path + ".ckpt" : opt.checkpoint_dir};
  const json fingerprint = config_fingerprint(arch, opt);
  int start_epoch = 0;
  json history = json::array();
  double best_val = -1;
  int best_epoch = -1;
  if (opt.resume && fs::exists(ck.state())) {
    std::ifstream in(ck.state());
    json st;
    try {
      st = json::parse(in);
    } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
      throw Error(ck.state() + ": not valid JSON (" + e.what() + "); remove the folder or pass --restart");
    }
    require(st.value("config", json()) == fingerprint,
            ck.state() + ": the checkpoint was made with other settings or data; pass --restart to start over");
    start_epoch = st.at("epoch").get<int>();
    load_archive(ck.model(start_epoch), net.module(), dev);
    load_archive(ck.optim(start_epoch), optim, dev);
    history = st.value("history", json::array());
    best_val = st.value("best_validation_cm", -1.0);
    best_epoch = st.value("best_epoch", -1);
    sum.resumed_from_epoch = start_epoch;
    if (opt.progress) std::fprintf(stderr, "[train] resuming after epoch %d from %s\n", start_epoch, ck.dir.c_str());
  }
  if (!opt.resume) fs::remove_all(ck.dir);
  fs::create_directories(ck.dir);

  auto save_checkpoint = [&](int next_epoch) {
    save_archive(ck.model(next_epoch), net.module());
    save_archive(ck.optim(next_epoch), optim);
    json st = {{"epoch", next_epoch}, {"config", fingerprint}, {"history", history},
               {"best_validation_cm", best_val}, {"best_epoch", best_epoch}};
    write_file_atomically(ck.state(), [&](std::ostream& o) { o << st.dump(1) << "\n"; });
    for (const auto& e : fs::directory_iterator(ck.dir)) {
      const std::string n = e.path().filename().string();
      const bool current = n == fs::path(ck.model(next_epoch)).filename().string() ||
                           n == fs::path(ck.optim(next_epoch)).filename().string();
      if (!current && (n.rfind("model-", 0) == 0 || n.rfind("optimizer-", 0) == 0)) fs::remove(e.path());
    }
  };

  const int64_t F = data.train.size();
  torch::Tensor frame_weights;  // F, on the CPU; undefined: the paper's loss
  if (opt.relative_floor_cm > 0) {
    require(arch.kind == "sr", "train: --relative-floor applies to the network, not the β-VAE");
    frame_weights = relative_frame_weights(data.train.hr, data.train.embedded, opt.relative_floor_cm);
  }
  Progress progress("train " + arch.kind, opt.epochs, opt.progress, start_epoch);
  double epoch_time_total = 0;
  int epochs_run = 0, since_best = 0;
  int epoch = start_epoch;
  net.module().train();
  bool budget_reached = false;
  for (; epoch < opt.epochs; ++epoch) {
    if (opt.time_budget_s > 0 && !history.empty()) {
      // Counts the epochs of earlier (killed or stopped) runs too, from the checkpoint's history.
      double spent = 0;
      int timed = 0;
      for (const auto& h : history)
        if (h.contains("seconds")) spent += h["seconds"].get<double>(), ++timed;
      if (timed > 0 && spent + spent / timed > opt.time_budget_s) {
        sum.hit_time_limit = budget_reached = true;
        break;
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    // Per-epoch seeds: a resumed run shuffles and samples as an unbroken one would.
    torch::manual_seed(opt.seed * 1000003ull + uint64_t(epoch));
    std::mt19937_64 rng(opt.seed * 7919ull + uint64_t(epoch));
    std::vector<int64_t> order(static_cast<size_t>(F));
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    const double beta = beta_schedule(epoch, opt.epochs, opt.beta_start, opt.beta_end);
    const double lr_now = learning_rate_schedule(epoch, opt.epochs, opt.learning_rate, opt.learning_rate_final);
    for (auto& group : optim.param_groups()) static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr_now);
    double loss_sum = 0, l1_sum = 0;
    int batches = 0;
    // A large dataset's epoch can take minutes on a CPU: report within it too.
    const int64_t batches_planned = (F + opt.batch_size - 1) / opt.batch_size;
    auto last_report = t0;
    for (int64_t b = 0; b < F; b += opt.batch_size) {
      const int64_t n = std::min<int64_t>(opt.batch_size, F - b);
      const auto idx = torch::from_blob(order.data() + b, {n}, torch::kLong).clone();
      const auto lr = data.train.lr.index_select(0, idx).to(dev);
      const auto hr = data.train.hr.index_select(0, idx).to(dev);
      optim.zero_grad();
      double l1 = 0;
      const torch::Tensor w = frame_weights.defined() ? frame_weights.index_select(0, idx).to(dev) : torch::Tensor();
      auto loss = net.loss(lr, hr, opt, beta, l1, w);
      require(std::isfinite(loss.item<double>()),
              "train: the loss became non-finite at epoch " + std::to_string(epoch + 1) +
                  " (try a lower --lr); the last checkpoint is kept");
      loss.backward();
      optim.step();
      loss_sum += loss.item<double>();
      l1_sum += l1;
      ++batches;
      if (opt.progress && seconds_since(last_report) >= 60 && batches < batches_planned) {
        last_report = std::chrono::steady_clock::now();
        const double el = seconds_since(t0);
        std::fprintf(stderr, "[train %s] epoch %d/%d: batch %d/%lld (%.0f%%), L1 %.4f cm/vertex so far, epoch ETA %.0fs\n",
                     arch.kind.c_str(), epoch + 1, opt.epochs, batches, (long long)batches_planned,
                     100.0 * batches / batches_planned, l1_sum / batches,
                     el * double(batches_planned - batches) / batches);
      }
    }
    const double train_loss = loss_sum / batches, train_l1 = l1_sum / batches;
    json rec = {{"epoch", epoch + 1}, {"loss", train_loss}, {"l1_cm", train_l1}, {"beta", beta}, {"lr", lr_now},
                {"seconds", seconds_since(t0)}};
    bool improved = false;
    if (data.validation.size() > 0) {
      const double v = mean_error_cm(net, data.validation, dev, opt.batch_size);
      rec["validation_cm"] = v;
      if (best_val < 0 || v < best_val) {
        best_val = v;
        best_epoch = epoch + 1;
        improved = true;
        save_archive(ck.best(), net.module());
      }
    }
    history.push_back(rec);
    since_best = improved || data.validation.size() == 0 ? 0 : since_best + 1;
    if (epochs_run == 0) {
      sum.first_loss = train_loss;
      sum.first_l1_cm = train_l1;
    }
    sum.final_loss = train_loss;
    sum.final_l1_cm = train_l1;
    ++epochs_run;
    epoch_time_total += seconds_since(t0);
    char detail[160];
    std::snprintf(detail, sizeof detail, "loss %.5f, L1 %.4f cm/vertex%s", train_loss, train_l1,
                  rec.contains("validation_cm")
                      ? (", validation " + std::to_string(rec["validation_cm"].get<double>()) + " cm").c_str()
                      : "");
    progress.update(epoch + 1, detail);
    const bool last = epoch + 1 == opt.epochs;
    sum.stopped_early = opt.patience > 0 && since_best >= opt.patience;
    sum.hit_time_limit = opt.time_limit_s > 0 && seconds_since(t_start) >= opt.time_limit_s;
    if (last || sum.stopped_early || sum.hit_time_limit || (epoch + 1) % opt.checkpoint_every == 0)
      save_checkpoint(epoch + 1);
    if (sum.stopped_early || sum.hit_time_limit) {
      ++epoch;
      break;
    }
  }
  if (epoch < opt.epochs) {
    if (opt.progress)
      std::fprintf(stderr, "[train %s] stopped after epoch %d of %d (%s)\n", arch.kind.c_str(), epoch, opt.epochs,
                   sum.stopped_early ? "early stop: no better validation error"
                   : budget_reached ? "time budget reached (epochs of every run counted)"
                       : "time limit; the same command resumes from the checkpoint");
  } else {
    progress.finish();
  }
  sum.epochs_done = epoch;
  sum.finished = epoch >= opt.epochs || sum.stopped_early;
  sum.best_epoch = best_epoch;
  sum.best_validation_cm = best_val;
  sum.train_time_s = seconds_since(t_start);
  sum.mean_epoch_s = epochs_run ? epoch_time_total / epochs_run : 0;

  // Export the best validation weights when there are any.
  if (best_epoch > 0 && fs::exists(ck.best())) load_archive(ck.best(), net.module(), dev);
  net.module().to(torch::kCPU);
  export_parameters(net.module(), model);
  model.training = sum.to_json();
  model.training["options"] = fingerprint;
  model.training["history"] = history;
  save_sr_model(opt.out_path, model);
  return sum;
}

}  // namespace facesr
