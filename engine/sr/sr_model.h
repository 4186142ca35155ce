#pragma once
// A trained super-resolution model (".fsm" file, version 6): the
// architecture, the rig it belongs to (by checksum, so a model cannot be
// paired with another rig), the rest-pose neighbourhoods it was trained with,
// and every parameter tensor. Read by evaluation and by the runtime without
// LibTorch. All integers and floats little-endian; strings and vectors are a
// u64 count then the elements.
//
//   offset  size  field
//   0       8     magic "FACESRSM"
//   8       4     u32 format version: 6 with pe_rows, else 5. Versions 4
//                   and 2 are still read: 4 and 2 have no residual
//                   smoothing, 2 no near-rest correctives. Version 3 had
//                   them in another form and is not read; version 1 had
//                   no surface embedding.
//   12            string header: JSON {"format": "facesr-sr-model", "version": 5 or 6,
//                   "units": "cm", "rig_name", "rig_checksum", "num_lr" (N),
//                   "num_hr" (M), "architecture": {...}, "training": {...},
//                   and "rest_correctives": {"shapes", "amplitudes" (a list
//                   per shape), "fade", "ridge"} when the model has them
//                   (sr/rest_correctives.h), and "residual_smoothing":
//                   {"operator": "umbrella", "lambda", "iterations"} when it
//                   has that (sr/residual_smoothing.h)}
//                 geometry (SrGeometry, k values from the architecture):
//                   vector<f32> lr_rest (N×3), hr_rest (M×3),
//                               hr_rest_lr_frame (M×3)
//                   vector<i32> hr_tris (T×3)
//                   vector<i32> lr_graph (N×graph_k), lr_to_hr (N),
//                               up_index (M×upsample_k)
//                   vector<f32> up_dist (M×upsample_k)
//                   vector<i32> euclid_index (M×upsample_k)
//                   vector<f32> euclid_dist (M×upsample_k)
//                   vector<u8>  up_is_euclid (M×upsample_k)
//                   vector<i32> embed_nodes (M×4), vector<f32> embed_weights (M×4)
//                               (the LR embedding of the surface; required with
//                               architecture.embedded_skip)
//                   vector<i32> pe_rows (version 6 only: N, the
//                               positional-encoding index per LR node, set
//                               by `facesr model transfer`)
//                   (for kind "vae" the neighbourhood vectors are empty)
//                 u64 tensor count T, then T tensors, each:
//                   string name, vector<i64> shape, vector<f32> values
//                   (in parameter_shapes() order, values row-major)
//                 vector<f32> rest corrective LR directions (S×N×3),
//                             rest corrective HR residuals (K×M×3, K the
//                             samples of all shapes, shape by shape)
//                   (both empty when the header has no "rest_correctives")
//   end - 8       u64 FNV-1a 64 of every byte before it
//
// Nothing may follow the checksum. Any layout change needs a new version.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sr/sr_architecture.h"
#include "sr/residual_smoothing.h"
#include "sr/rest_correctives.h"
#include "sr/sr_geometry.h"

namespace facesr {

struct SrTensor {
  std::string name;
  std::vector<int64_t> shape;
  std::vector<float> values;  // row-major, product(shape) values
};

struct SrModel {
  SrArchitecture arch;
  std::string rig_name;
  uint64_t rig_checksum = 0;
  int num_lr = 0, num_hr = 0;  // N, M
  SrGeometry geometry;
  std::vector<SrTensor> tensors;
  RestCorrectives rest_correctives;  // empty: none (the network alone)
  ResidualSmoothing residual_smoothing;  // empty (0 iterations): none
  nlohmann::json training = nlohmann::json::object();  // how it was trained (free-form record)

  // The tensor with this name; Error if absent.
  const SrTensor& tensor(const std::string& name) const;
};

// Checks sizes, names and shapes against parameter_shapes(), index ranges
// and finiteness. Errors start with `context`.
void validate_sr_model(const SrModel& m, const std::string& context);

// Validates, then writes atomically (no partial file on failure).
void save_sr_model(const std::string& path, const SrModel& m);

// Reads and validates; every Error names `path` (missing, truncated, corrupt,
// wrong version, inconsistent).
SrModel load_sr_model(const std::string& path);

// Error unless the model was trained on the rig with this checksum and sizes.
void require_model_matches_rig(const SrModel& m, uint64_t rig_checksum, int num_lr, int num_hr,
                               const std::string& model_name, const std::string& rig_name);

}  // namespace facesr
