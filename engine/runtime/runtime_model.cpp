#include "runtime/runtime_model.h"

#include "core/error.h"
#include "rig/rig_io.h"

namespace facesr {

std::shared_ptr<const RuntimeModel> compile_runtime_model(std::shared_ptr<const Rig> rig,
                                                          std::shared_ptr<const SrModel> model,
                                                          std::optional<uint64_t> rig_checksum) {
  require(rig && model, "runtime: a rig and a model are needed");
  require(model->arch.kind == "sr", "runtime: the model is a '" + model->arch.kind + "' model, not the network");
  auto m = std::make_shared<RuntimeModel>();
  m->rig_checksum = rig_checksum ? *rig_checksum : facesr::rig_checksum(*rig);
  require_model_matches_rig(*model, m->rig_checksum, int(rig->lr.mesh.X.rows()), rig->num_surface_vertices(),
                            "the model", "rig '" + rig->name + "'");
  m->lr_model = make_sim_model(*rig, Resolution::Low);
  m->plan = std::make_shared<const SrInferencePlan>(make_inference_plan(*model));
  m->hr_rest.assign(rig->surface.data(), rig->surface.data() + rig->surface.size());
  m->rig = std::move(rig);
  m->model = std::move(model);
  return m;
}

}  // namespace facesr
