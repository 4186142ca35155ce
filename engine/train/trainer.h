#pragma once
// `facesr train`: fits the super-resolution network (or the β-VAE baseline)
// to a paired dataset with Adam, deterministic seeds, checkpoints every few
// epochs that a rerun resumes from, optional early stopping on held-out
// training frames, and export to the engine's model file.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "rig/rig.h"
#include "sr/sr_architecture.h"
#include "sr/sr_model.h"

namespace facesr {

struct TrainOptions {
  std::string dataset_dir;     // from `facesr dataset`
  std::string out_path;        // the model file (.fsm)
  std::string checkpoint_dir;  // default: out_path + ".ckpt"
  int epochs = 2800;           // the paper trained 2,800 epochs
  int batch_size = 6;          // the paper's
  double learning_rate = 1e-4;  // the paper's (Adam)
  double learning_rate_final = 0;  // > 0: cosine-anneal to this by the last epoch (train/lr_schedule.h)
  // Start from this model file's weights (same rig and architecture, e.g. one
  // carried over by `facesr model transfer`, whose per-node encodings are kept; its
  // input/output scales are kept) instead of a random initialisation.
  std::string init_from;
  double alpha = 1e-3;          // face-normal loss weight (table 3)
  double beta_start = 1e-3, beta_end = 20;  // feature-norm weight ramp (table 3)
  double vae_beta = 0.01;       // KL weight of the β-VAE (A.4)
  // > 0 (not in the paper, network only): weight each training frame's L1
  // term by relative_frame_weights(…, relative_floor_cm) (train/sr_loss.h).
  double relative_floor_cm = 0;
  int checkpoint_every = 10;    // epochs
  int validation_every = 10;    // hold out every n-th training frame (0: none)
  bool keep_capped = false;     // train on HR frames that stopped above the Newton tolerance too
  int patience = 0;             // > 0: stop after this many epochs without a better validation error
  double time_limit_s = 0;      // > 0: checkpoint and stop after this much wall time (resume later)
  // > 0: do not start an epoch that would take the epochs' total wall time,
  // earlier runs of a resumed training included, past this (the mean epoch
  // so far is the estimate). Not part of the checkpoint's settings.
  double time_budget_s = 0;
  // Continue from a matching checkpoint (same data and settings; --epochs may
  // be raised to extend a run, and β's ramp then spans the new total).
  bool resume = true;
  uint64_t seed = 1;
  std::string device = "auto";  // cpu | cuda | auto
  bool progress = true;
};

struct TrainSummary {
  std::string kind, device;
  int epochs_planned = 0, epochs_done = 0, resumed_from_epoch = 0, best_epoch = -1;
  int train_frames = 0, validation_frames = 0;
  int capped_left_out = 0;  // train-split frames whose HR solve stopped above tolerance (see load_dataset_split)
  int64_t parameters = 0;
  double first_loss = 0, final_loss = 0;  // training loss of the first and last epoch run
  // Mean L1 error per HR vertex on the training batches of those epochs (cm);
  // unlike the loss it does not grow with the β ramp.
  double first_l1_cm = 0, final_l1_cm = 0;
  double best_validation_cm = -1;         // mean per-vertex error on the validation frames
  double train_time_s = 0, mean_epoch_s = 0;
  bool stopped_early = false, hit_time_limit = false, finished = false;
  nlohmann::json to_json() const;
};

// Trains, writes checkpoints, and writes the model file when training ends
// (all epochs, early stop or time limit; the exported weights are those of
// the best validation epoch when there is a validation set). The model's
// rig checksum is the rig's. Errors (bad dataset, other rig, bad options)
// are thrown before anything is written.
TrainSummary train_model(const Rig& rig, const SrArchitecture& arch, const TrainOptions& opt);

}  // namespace facesr
