#pragma once
// Carrying a trained super-resolution model over to another rig (another
// face): the network is shared MLPs over points and neighbourhoods (paper
// §3), so its weights do not belong to one rig; everything that does is
// recomputed for the new rig and the weights are kept. Not in the paper.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rig/rig.h"
#include "sr/sr_model.h"

namespace facesr {

struct ModelTransferReport {
  std::string from_rig, to_rig;
  uint64_t from_checksum = 0, to_checksum = 0;
  int from_lr = 0, from_hr = 0, to_lr = 0, to_hr = 0;
  size_t parameters_kept = 0;
  std::vector<std::string> recomputed;  // what was rebuilt for the new rig
  std::vector<std::string> kept;        // settings carried over unchanged
  int correctives_dropped = 0;          // near-rest correctives (shapes) left out
  // Distance from each new LR node to the old node whose positional encoding
  // it takes, both in their model's normalised frame, times the new frame's
  // scale (cm on the new head): how well the two lattices line up.
  double pe_match_mean_cm = 0, pe_match_max_cm = 0;
  nlohmann::json to_json() const;
};

// The model bound to `rig` (checksum `rig_checksum`): graphs, neighbourhoods,
// upsampling inputs, embedding, rest poses and the SIREN coordinate frame
// rebuilt from the rig with the model's k values; each new LR node given the
// positional encoding of the old node nearest to it once both heads are
// normalised to their own frames (sr/coordinate_frame.h). Parameter tensors,
// data scales, zero_rest and the residual smoothing settings are kept. Near-
// rest correctives are fitted on one rig's data and are dropped (fit them
// again with `facesr model correctives` on the new rig's dataset). Errors
// for models whose parameters are sized by the rig: the VAE baseline (an
// output layer of 3M) and the ablation without coordinate-based upsampling
// (free weights per HR vertex).
SrModel transfer_sr_model(const SrModel& m, const Rig& rig, uint64_t rig_checksum, ModelTransferReport* report,
                          const std::string& context);

}  // namespace facesr
