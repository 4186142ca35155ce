#include "sr/sr_model_blend.h"

#include <cmath>

#include "core/error.h"
#include "sr/sr_architecture.h"
#include "sr/sr_geometry_compare.h"

namespace facesr {

SrModel blend_sr_models(const SrModel& a, const SrModel& b, double t, const std::string& context) {
  require(std::isfinite(t) && t >= 0 && t <= 1, context + ": blend factor " + std::to_string(t) + " is not in [0, 1]");
  require(a.rig_name == b.rig_name && a.rig_checksum == b.rig_checksum,
          context + ": the models belong to different rigs ('" + a.rig_name + "' and '" + b.rig_name + "')");
  require(a.num_lr == b.num_lr && a.num_hr == b.num_hr, context + ": the models have different LR/HR sizes");
  const nlohmann::json ja = architecture_to_json(a.arch), jb = architecture_to_json(b.arch);
  for (const auto& [key, value] : ja.items())
    require(jb.contains(key) && jb.at(key) == value, context + ": the models have different architectures (" + key +
                                                         ": " + value.dump() + " vs " + jb.value(key, nlohmann::json()).dump() + ")");
  // Weights only mean the same thing over the same neighbourhoods and rest poses.
  const SrGeometryDifference d = compare_sr_geometry(a.geometry, b.geometry);
  require(d.topology_mismatch.empty(), context + ": the models' " + d.topology_mismatch + " differ");
  require(d.max_position_cm == 0 && d.max_distance_cm == 0 && d.max_weight == 0,
          context + ": the models' rest-pose geometry differs (by up to " + std::to_string(d.max_position_cm) +
              " cm)");
  require(a.geometry.pe_rows == b.geometry.pe_rows,
          context + ": the models give their LR nodes different positional encodings (geometry.pe_rows)");
  // Correctives measure one network's residual; a blend is another network.
  require(a.rest_correctives.empty() && b.rest_correctives.empty(),
          context + ": a model has near-rest correctives; blend the models without them, then fit them again "
                    "(`facesr model correctives`)");
  require(a.residual_smoothing.lambda == b.residual_smoothing.lambda &&
              a.residual_smoothing.iterations == b.residual_smoothing.iterations,
          context + ": the models have different residual smoothing (`facesr model smooth` both the same way)");
  require(a.tensors.size() == b.tensors.size(), context + ": the models have different parameter counts");
  SrModel out = a;
  for (size_t i = 0; i < a.tensors.size(); ++i) {
    const SrTensor &x = a.tensors[i], &y = b.tensors[i];
    require(x.name == y.name && x.shape == y.shape, context + ": parameter " + x.name + " differs in name or shape");
    for (size_t k = 0; k < x.values.size(); ++k)
      out.tensors[i].values[k] = float((1 - t) * double(x.values[k]) + t * double(y.values[k]));
  }
  out.training = nlohmann::json::object();
  out.training["blend"] = {{"t", t}, {"a", a.training}, {"b", b.training}};
  return out;
}

}  // namespace facesr
