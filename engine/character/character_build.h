#pragma once
// `facesr character build`: one command from a head to a shipped real-time
// model. Stages, each recorded in <out>/character.json when it finishes and
// skipped by a rerun of the same command (a killed run resumes; the dataset
// and training stages also resume inside themselves):
//   rig        rig build + preview PNG
//   test_data  LR + HR simulation of the test split (anger, fear); its HR
//              time per frame sizes the training data
//   train_data the training takes that fit the budget (character_recipe.h)
//   train_a    training (embedded skip), or fine-tuning a transferred model
//   train_b    annealed fine-tune with zero_rest
//   post_fit   residual smoothing and near-rest correctives, each kept only
//              if it lowers the error on the validation frames
//   evaluate   ours and embedded on the test split
//   package    model.fsm, rig, report, preview, glTF of a test take, manifest
#include <string>

#include <nlohmann/json.hpp>

#include "sr/sr_architecture.h"

namespace facesr {

struct CharacterOptions {
  std::string source;   // ICT-layout head folder, or "procedural"
  std::string out_dir;  // the package (created)
  double budget_s = 3 * 3600.0;
  std::string init_from;  // a trained model (of any rig): transferred to this rig, then fine-tuned
  std::string preset = "default";  // rig build preset (rig/rig_preset.h)
  int max_frames = 0;    // > 0: at most this many frames per performance (tiny runs)
  int max_epochs = 1000;  // cap of each training stage (the budget normally stops it first)
  int validation_every = 10;
  std::string device = "auto";  // training device
  bool restart = false;  // discard the folder's earlier stages
  bool progress = true;
  uint64_t seed = 1;
};

// Runs (or resumes) the pipeline and returns its summary: every stage's
// record (settings, seconds, results), the test-split errors
// (ours_mean_cm, embedded_mean_cm, ours_over_embedded,
// frames_ours_beats_embedded), the files written, the machine, units "cm".
// Errors before any long work for a bad head (missing shapes, other vertex
// counts), a model file that cannot be transferred, or a folder holding a
// build with other settings.
nlohmann::json build_character(const CharacterOptions& opt);

// The architecture a character is trained with: the paper's network with
// the embedded skip (BENCHMARKS.md, ICT stages 1–9).
SrArchitecture character_architecture();

}  // namespace facesr
