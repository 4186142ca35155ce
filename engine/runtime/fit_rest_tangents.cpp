#include "runtime/fit_rest_tangents.h"

#include <cmath>
#include <map>
#include <memory>

#include "core/error.h"
#include "core/framed_file.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "runtime/sr_inference.h"

namespace facesr {
namespace {

struct Pick {
  std::string sequence;
  int frame = -1;
  double weight = 0;
  std::vector<float> lr, hr;  // the frame's LR and HR displacements
};

double mean_error_cm(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0;
  for (size_t v = 0; v < a.size() / 3; ++v)
    sum += std::hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]);
  return sum / double(a.size() / 3);
}

}  // namespace

RestTangentFit fit_rest_tangents(const SrModel& model, const std::string& dir, const RestTangentFitOptions& opt) {
  require(model.arch.kind == "sr", "rest tangents: the model is a '" + model.arch.kind +
                                       "' model; they apply to the super-resolution network");
  require(opt.validation_every == 0 || opt.validation_every >= 2, "rest tangents: --validation-every must be 0 or >= 2");
  require(std::isfinite(opt.max_weight) && opt.max_weight > 0, "rest tangents: --max-weight must be positive");
  const DatasetManifest man = load_manifest(dir + "/manifest.json");
  require(man.rig_checksum == model.rig_checksum,
          dir + ": the dataset was made from rig '" + man.rig_name + "' (checksum " + hex64(man.rig_checksum) +
              "), the model belongs to '" + model.rig_name + "' (" + hex64(model.rig_checksum) + ")");
  require(man.num_lr_nodes == model.num_lr && man.num_surface == model.num_hr,
          dir + ": the dataset has " + std::to_string(man.num_lr_nodes) + " LR nodes and " +
              std::to_string(man.num_surface) + " surface vertices, the model " + std::to_string(model.num_lr) +
              " and " + std::to_string(model.num_hr));

  // Smallest single-shape frame per shape, over the training frames.
  std::map<std::string, Pick> picks;
  for (const auto& e : man.sequences) {
    if (e.split != "train") continue;
    require(e.complete, dir + ": sequence '" + e.name + "' is not complete; finish it with `facesr dataset`");
    const DatasetSequence s = read_dataset_sequence(dir + "/" + e.file);
    for (int f = 0; f < s.num_frames(); ++f) {
      if (is_validation_frame(f, opt.validation_every)) continue;
      const DatasetFrame& fr = s.frame(f);
      int active = -1, count = 0;
      for (size_t b = 0; b < fr.weights.size(); ++b)
        if (fr.weights[b] != 0) active = int(b), ++count;
      if (count != 1) continue;
      const double w = fr.weights[size_t(active)];
      if (!(w > 0 && w <= opt.max_weight)) continue;
      const std::string& name = s.header.weight_names[size_t(active)];
      auto it = picks.find(name);
      if (it != picks.end() && it->second.weight <= w) continue;
      picks[name] = {e.name, f, w, fr.lr_disp, fr.hr_disp};
    }
  }
  require(!picks.empty(), dir + ": no training frame has a single blendshape active at a weight in (0, " +
                              std::to_string(opt.max_weight) + "]; add the built-in \"nudge\" performance");

  SrModel net = model;
  net.rest_tangents = {};
  auto inference = make_cpu_inference(std::make_shared<const SrModel>(net));
  RestTangentFit fit;
  RestTangents& t = fit.tangents;
  t.fade = opt.fade;
  t.ridge = opt.ridge;
  const size_t N3 = 3 * size_t(model.num_lr), M3 = 3 * size_t(model.num_hr);
  std::vector<std::vector<float>> predicted;
  for (const auto& [name, p] : picks) {
    std::vector<float> y(M3);
    inference->infer(p.lr.data(), y.data());
    t.shapes.push_back(name);
    t.amplitudes.push_back(float(p.weight));
    for (size_t i = 0; i < N3; ++i) t.lr.push_back(float(p.lr[i] / p.weight));
    // Divided by φ at the frame too, so that the corrected model reproduces
    // the frame it was measured on rather than a faded share of it.
    const double u = (p.weight / opt.fade) * (p.weight / opt.fade);
    const double gain = p.weight * std::exp(-u * u);  // RestTangentCorrection::fade_factor
    for (size_t i = 0; i < M3; ++i) t.hr.push_back(float((p.hr[i] - y[i]) / gain));
    predicted.push_back(std::move(y));
  }
  validate_rest_tangents(t, model.num_lr, model.num_hr, dir);
  const RestTangentCorrection correction(t, model.num_lr, model.num_hr);
  size_t s = 0;
  for (const auto& [name, p] : picks) {
    std::vector<float> corrected = predicted[s++];
    correction.apply(p.lr.data(), corrected.data());
    fit.shapes.push_back({{"shape", name},
                          {"sequence", p.sequence},
                          {"frame", p.frame},
                          {"weight", p.weight},
                          {"network_error_cm", mean_error_cm(predicted[s - 1], p.hr)},
                          {"corrected_error_cm", mean_error_cm(corrected, p.hr)}});
  }
  for (const auto& n : man.weight_names)
    if (!picks.count(n)) fit.unmeasured.push_back(n);
  return fit;
}

}  // namespace facesr
