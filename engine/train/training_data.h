#pragma once
// Paired frames of a dataset (engine/dataset) as tensors for training and
// evaluation: the manifest's train split minus a held-out validation subset,
// and its test split.
#include <array>
#include <string>
#include <vector>

#include <torch/torch.h>

namespace facesr {

struct FrameSet {
  torch::Tensor lr;        // F × N × 3 LR node displacements, cm
  torch::Tensor hr;        // F × M × 3 HR surface displacements, cm
  torch::Tensor embedded;  // F × M × 3 LR-embedded surface displacements, cm
  std::vector<std::string> sequence;  // per frame
  std::vector<int> frame;             // per frame, index in its sequence
  std::vector<std::vector<float>> weights;  // per frame, its ARKit weights (the dataset's weight_names order)
  std::vector<std::array<float, 12>> jaw;   // per frame, the jaw's R (row-major) and t (cm)
  int64_t size() const { return lr.defined() ? lr.size(0) : 0; }
};

struct DatasetSplit {
  FrameSet train, validation, test;
  int num_lr = 0, num_hr = 0;
  std::vector<std::string> weight_names;  // the manifest's blendshape order of FrameSet::weights
  // Train-split frames left out because their HR solve stopped above the
  // dataset's Newton tolerance (manifest extra "hr_newton_tol", 1e-3 when
  // absent): capped or diverged references would teach the network a wrong
  // surface. Test frames are all kept, so evaluations stay comparable.
  int capped_left_out = 0;
};

// Reads <dir>/manifest.json and its sequences. Every `validation_every`-th
// training frame (0: none) goes to the validation set, used for early
// stopping and for choosing the exported weights; the test split is never
// used in training. Error if the dataset was made from another rig, has no
// training frames (when require_train), or any sequence is incomplete or
// damaged.
DatasetSplit load_dataset_split(const std::string& dir, uint64_t rig_checksum, int validation_every,
                                bool require_train = true, bool keep_capped = false);

}  // namespace facesr
