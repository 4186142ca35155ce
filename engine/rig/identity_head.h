#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace facesr {

// A new head in the ICT FaceKit identity model, written in the layout of the
// generic FaceKit folder (so `rig build --source` takes it unchanged):
//   neutral  = generic + Σ_k w_k · (identity_k − generic)
//   shape_s  = neutral + (expression_s − generic)
// Units: centimetres, like the generic head.
struct IdentityHeadSpec {
  std::string ict_dir;         // the generic FaceKit folder (neutral, expressions, vertex_indices.json)
  std::string identities_dir;  // identity000.obj … (one standard deviation each)
  std::vector<double> weights; // w_k in standard deviations; mode k is identity%03d.obj
};

struct IdentityHeadReport {
  int modes = 0;
  int expressions = 0;
  int vertices = 0;
  double max_offset_cm = 0;  // largest |neutral − generic| over vertices
};

// Identity modes found in `identities_dir` (identity000.obj, identity001.obj, … without gaps).
int count_identity_modes(const std::string& identities_dir);

// Weights for `modes` modes drawn uniformly in [−max_sigma, max_sigma] from
// `seed` (uniform rather than normal so that a small corpus of heads reaches
// the extremes a robustness test is for).
std::vector<double> random_identity_weights(uint32_t seed, int modes, double max_sigma);

// Writes the head into `out_dir` (created; must not hold another head).
// Throws Error naming the file on missing or mismatched meshes, before
// writing anything.
IdentityHeadReport write_identity_head(const IdentityHeadSpec& spec, const std::string& out_dir);

}  // namespace facesr
