#include "capi_internal.h"

namespace facesr::capi {

std::shared_ptr<const RuntimeModel> CompiledModels::get(const std::shared_ptr<const LoadedRig>& rig,
                                                        const std::shared_ptr<const SrModel>& model) {
  // Compiling under the lock: a second thread asking for the same rig waits
  // for the first one's result instead of compiling it again.
  std::lock_guard<std::mutex> lock(mu_);
  std::shared_ptr<const RuntimeModel> found;
  std::vector<Entry> live;
  for (Entry& e : entries_) {
    std::shared_ptr<const RuntimeModel> c = e.compiled.lock();
    std::shared_ptr<const LoadedRig> r = e.rig.lock();
    if (!c || !r) continue;  // every context on it is gone, or the rig was freed
    if (r == rig) found = c;
    live.push_back(std::move(e));
  }
  entries_ = std::move(live);
  if (found) return found;
  auto compiled = compile_runtime_model(rig->rig, model, rig->checksum);
  entries_.push_back({rig, compiled});
  return compiled;
}

}  // namespace facesr::capi
