// facesr train: the super-resolution network or the β-VAE baseline
// (engine/train/trainer.h).
#include <cstdio>

#include <nlohmann/json.hpp>

#include "bench/bench_report.h"
#include "arg_lists.h"
#include "commands.h"
#include "core/error.h"
#include "rig/rig_io.h"
#include "train/trainer.h"

namespace facesr::cli {

void register_train(CLI::App& app) {
  struct Args {
    std::string rig, dataset, out, checkpoints, kind = "sr", device = "auto";
    std::string encoder_dims = "64,128", weight_hidden = "64,64", recon_hidden = "128,128,128";
    int graph_k = 5, neighbours = 20, pe_dim = 32;
    bool no_fe = false, no_cu = false, skip = false, zero_rest = false, restart = false, json = false, quiet = false;
    TrainOptions o;
  };
  static Args a;
  auto* sub = app.add_subcommand("train", "Train the super-resolution network (or the β-VAE baseline) on a dataset");
  sub->add_option("--rig", a.rig, "Rig file the dataset was made from")->required();
  sub->add_option("--dataset", a.dataset, "Dataset folder (from `facesr dataset`)")->required();
  sub->add_option("--out,-o", a.out, "Output model file (.fsm)")->required();
  sub->add_option("--kind", a.kind, "sr (the paper's network, default) | vae (the β-VAE baseline)");
  sub->add_option("--epochs", a.o.epochs, "Epochs (default 2800, the paper's)");
  sub->add_option("--batch", a.o.batch_size, "Frames per batch (default 6, the paper's)");
  sub->add_option("--lr", a.o.learning_rate, "Adam learning rate (default 1e-4, the paper's)");
  sub->add_option("--lr-final", a.o.learning_rate_final,
                  "Not in the paper: cosine-anneal the learning rate to this by the last epoch (default: constant)");
  sub->add_option("--init-from", a.o.init_from,
                  "Start from this model file's weights (same rig and architecture) instead of random ones");
  sub->add_option("--alpha", a.o.alpha, "Face-normal loss weight (default 0.001)");
  sub->add_option("--beta-start", a.o.beta_start, "Feature-norm loss weight at the first epoch (default 0.001)");
  sub->add_option("--beta-end", a.o.beta_end, "Feature-norm loss weight at the last epoch (default 20)");
  sub->add_option("--vae-beta", a.o.vae_beta, "β-VAE KL weight (default 0.01)");
  sub->add_option("--relative-floor", a.o.relative_floor_cm,
                  "Not in the paper: weight each frame's L1 term by 1/(its LR-embedded error + this, cm), mean 1, "
                  "so that frames near rest count relative to their size (default 0: unweighted)");
  sub->add_option("--checkpoint-every", a.o.checkpoint_every, "Epochs between checkpoints (default 10)");
  sub->add_option("--checkpoints", a.checkpoints, "Checkpoint folder (default <out>.ckpt)");
  sub->add_option("--validation-every", a.o.validation_every,
                  "Hold out every n-th training frame for validation (default 10; 0: none)");
  sub->add_flag("--keep-capped", a.o.keep_capped,
                "Train on HR frames that stopped above the dataset's Newton tolerance too (default: left out, counted "
                "in capped_left_out)");
  sub->add_option("--patience", a.o.patience, "Early stop after this many epochs without a better validation error");
  sub->add_option("--time-limit", a.o.time_limit_s, "Checkpoint, export and stop after this many seconds");
  sub->add_option("--time-budget", a.o.time_budget_s,
                  "Do not start an epoch that would take the epochs' total time, resumed runs included, past this many seconds");
  sub->add_flag("--restart", a.restart, "Ignore and remove an existing checkpoint instead of resuming");
  sub->add_option("--seed", a.o.seed, "Random seed (default 1)");
  sub->add_option("--device", a.device, "cpu | cuda | auto (default: CUDA when this LibTorch has it)");
  sub->add_flag("--no-fe", a.no_fe, "Ablation: no feature encoding (positional-encoded input goes to the upsampling)");
  sub->add_flag("--no-cu", a.no_cu,
                "Ablation: no coordinate-based upsampling (learned weights over the Euclidean-nearest LR nodes)");
  sub->add_flag("--embedded-skip", a.skip,
                "Not in the paper: learn the correction to the LR-embedded surface (a residual connection)");
  sub->add_flag("--zero-rest", a.zero_rest,
                "Not in the paper: subtract the output at the rest input, so that rest maps exactly to rest");
  sub->add_option("--neighbours", a.neighbours, "Interpolation neighbours per HR vertex (default 20)");
  sub->add_option("--graph-k", a.graph_k, "k of the EdgeConv k-NN graphs (default 5)");
  sub->add_option("--pe-dim", a.pe_dim, "Positional encoding size (default 32)");
  sub->add_option("--encoder-dims", a.encoder_dims, "Feature widths of the EdgeConv submodules (default 64,128)");
  sub->add_option("--weight-hidden", a.weight_hidden, "Hidden widths of the upsampling SIREN (default 64,64)");
  sub->add_option("--recon-hidden", a.recon_hidden, "Hidden widths of the reconstruction SIREN (default 128,128,128)");
  sub->add_flag("--json", a.json,
                "Print a JSON summary: kind, epochs, first_loss, final_loss, best_validation_cm, best_epoch, "
                "train_time_s, mean_epoch_s, parameters, device");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  add_action(sub, [] {
    require(a.kind == "sr" || a.kind == "vae", "--kind must be sr or vae, not '" + a.kind + "'");
    SrArchitecture arch;
    arch.kind = a.kind;
    arch.feature_encoding = !a.no_fe;
    arch.coordinate_upsampling = !a.no_cu;
    arch.embedded_skip = a.skip;
    arch.zero_rest = a.zero_rest;
    require(a.neighbours >= 1 && a.neighbours <= 64, "--neighbours must be in [1, 64]");
    require(a.graph_k >= 1 && a.graph_k <= 64, "--graph-k must be in [1, 64]");
    require(a.pe_dim >= 0 && a.pe_dim % 2 == 0 && a.pe_dim <= 1024, "--pe-dim must be even, in [0, 1024]");
    arch.upsample_k = a.neighbours;
    arch.graph_k = a.graph_k;
    arch.pe_dim = a.pe_dim;
    arch.encoder_dims = int_list(a.encoder_dims, "--encoder-dims");
    arch.weight_hidden = int_list(a.weight_hidden, "--weight-hidden");
    arch.recon_hidden = int_list(a.recon_hidden, "--recon-hidden");
    require(!arch.recon_hidden.empty(), "--recon-hidden needs at least one width");
    TrainOptions o = a.o;
    o.dataset_dir = a.dataset;
    o.out_path = a.out;
    o.checkpoint_dir = a.checkpoints;
    o.resume = !a.restart;
    o.device = a.device;
    o.progress = !a.quiet;
    const Rig rig = load_rig(a.rig);
    const TrainSummary s = train_model(rig, arch, o);
    nlohmann::json j = s.to_json();
    j["out"] = a.out;
    j["machine"] = machine_description();
    j["date"] = today_iso();
    if (a.json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("wrote %s: %s model, %d epochs in %.1f min (%.2f s/epoch), loss %.5f -> %.5f, best validation "
                  "error %.4f cm at epoch %d\n",
                  a.out.c_str(), s.kind.c_str(), s.epochs_done, s.train_time_s / 60, s.mean_epoch_s, s.first_loss,
                  s.final_loss, s.best_validation_cm, s.best_epoch);
    }
  });
}

}  // namespace facesr::cli
