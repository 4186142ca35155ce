#include "sr/model_transfer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/framed_file.h"
#include "core/error.h"
#include "sr/coordinate_frame.h"

namespace facesr {

nlohmann::json ModelTransferReport::to_json() const {
  return {{"from_rig", from_rig},
          {"to_rig", to_rig},
          {"from_checksum", hex64(from_checksum)},
          {"to_checksum", hex64(to_checksum)},
          {"from_num_lr", from_lr},
          {"from_num_hr", from_hr},
          {"to_num_lr", to_lr},
          {"to_num_hr", to_hr},
          {"parameters_kept", parameters_kept},
          {"recomputed", recomputed},
          {"kept", kept},
          {"rest_correctives_dropped", correctives_dropped},
          {"pe_match_mean_cm", pe_match_mean_cm},
          {"pe_match_max_cm", pe_match_max_cm},
          {"units", "cm"}};
}

namespace {

// Per new node, the old node nearest to it in normalised coordinates. Brute
// force: N_new × N_old is at most ~10⁸ distance evaluations for the largest
// lattices (well under a second), run once per transfer; a k-d tree would
// add a dependency for a one-off command.
std::vector<int32_t> nearest_old_nodes(const SrArchitecture& from, const std::vector<float>& old_rest,
                                       const SrArchitecture& to, const std::vector<float>& new_rest,
                                       double& mean_cm, double& max_cm) {
  const size_t n_old = old_rest.size() / 3, n_new = new_rest.size() / 3;
  std::vector<float> a(old_rest.size());
  for (size_t i = 0; i < n_old; ++i)
    for (int c = 0; c < 3; ++c) a[3 * i + c] = float((old_rest[3 * i + c] - from.coord_center[c]) / from.coord_scale);
  std::vector<int32_t> out(n_new);
  double sum = 0;
  max_cm = 0;
  for (size_t j = 0; j < n_new; ++j) {
    float q[3];
    for (int c = 0; c < 3; ++c) q[c] = float((new_rest[3 * j + c] - to.coord_center[c]) / to.coord_scale);
    float best = std::numeric_limits<float>::max();
    size_t arg = 0;
    for (size_t i = 0; i < n_old; ++i) {
      const float dx = a[3 * i] - q[0], dy = a[3 * i + 1] - q[1], dz = a[3 * i + 2] - q[2];
      const float d = dx * dx + dy * dy + dz * dz;
      if (d < best) best = d, arg = i;
    }
    out[j] = int32_t(arg);
    const double cm = std::sqrt(double(best)) * to.coord_scale;
    sum += cm;
    max_cm = std::max(max_cm, cm);
  }
  mean_cm = n_new ? sum / double(n_new) : 0;
  return out;
}

}  // namespace

SrModel transfer_sr_model(const SrModel& m, const Rig& rig, uint64_t rig_checksum, ModelTransferReport* report,
                          const std::string& context) {
  require(m.arch.kind == "sr", context + ": a '" + m.arch.kind +
                                   "' model has layers sized by its rig's vertex count and cannot be transferred; "
                                   "train one for the new rig");
  require(m.arch.coordinate_upsampling,
          context + ": the model has free upsampling weights per HR vertex (the ablation without coordinate-based "
                    "upsampling) and cannot be transferred; train one for the new rig");
  SrModel out;
  out.arch = m.arch;
  out.rig_name = rig.name;
  out.rig_checksum = rig_checksum;
  out.geometry = build_sr_geometry(rig, {m.geometry.graph_k, m.geometry.upsample_k});
  out.num_lr = out.geometry.num_lr;
  out.num_hr = out.geometry.num_hr;
  set_coordinate_frame(out.arch, out.geometry);
  ModelTransferReport r;
  const std::vector<int32_t> nearest =
      nearest_old_nodes(m.arch, m.geometry.lr_rest, out.arch, out.geometry.lr_rest, r.pe_match_mean_cm, r.pe_match_max_cm);
  out.geometry.pe_rows.resize(nearest.size());
  for (size_t j = 0; j < nearest.size(); ++j)
    out.geometry.pe_rows[j] = m.geometry.pe_rows.empty() ? nearest[j] : m.geometry.pe_rows[size_t(nearest[j])];
  out.tensors = m.tensors;  // shapes depend on the architecture only (checked by validate below)
  out.residual_smoothing = m.residual_smoothing;
  out.training = m.training;
  r.from_rig = m.rig_name;
  r.to_rig = rig.name;
  r.from_checksum = m.rig_checksum;
  r.to_checksum = rig_checksum;
  r.from_lr = m.num_lr;
  r.from_hr = m.num_hr;
  r.to_lr = out.num_lr;
  r.to_hr = out.num_hr;
  for (const SrTensor& t : m.tensors) r.parameters_kept += t.values.size();
  r.recomputed = {"lr_rest", "hr_rest", "hr_rest_lr_frame", "hr_tris", "lr_graph", "lr_to_hr", "up_index",
                  "up_dist", "euclid_index", "euclid_dist", "up_is_euclid", "embed_nodes", "embed_weights",
                  "pe_rows", "coord_center", "coord_scale"};
  r.kept = {"parameters", "input_scale", "output_scale", "zero_rest", "embedded_skip"};
  if (!m.residual_smoothing.empty()) r.kept.push_back("residual_smoothing");
  r.correctives_dropped = m.rest_correctives.count();
  out.training["transferred"].push_back({{"from_rig", r.from_rig},
                                         {"from_checksum", hex64(r.from_checksum)},
                                         {"rest_correctives_dropped", r.correctives_dropped},
                                         {"pe_match_mean_cm", r.pe_match_mean_cm}});
  validate_sr_model(out, context);
  if (report) *report = r;
  return out;
}

}  // namespace facesr
