#include "postfit/fit_rest_correctives.h"

#include <algorithm>
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

struct Sample {
  std::string sequence;
  int frame = -1;
  double weight = 0;
  std::vector<float> lr, hr;  // the frame's LR and HR displacements
  std::vector<float> predicted;
};

double mean_error_cm(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0;
  for (size_t v = 0; v < a.size() / 3; ++v)
    sum += std::hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]);
  return sum / double(a.size() / 3);
}

}  // namespace

RestCorrectiveFit fit_rest_correctives(const SrModel& model, const std::string& dir,
                                       const RestCorrectiveFitOptions& opt) {
  const std::string ctx = "rest correctives: ";
  require(model.arch.kind == "sr",
          ctx + "the model is a '" + model.arch.kind + "' model; they apply to the super-resolution network");
  require(opt.validation_every == 0 || opt.validation_every >= 2, ctx + "--validation-every must be 0 or >= 2");
  require(std::isfinite(opt.max_weight) && opt.max_weight > 0, ctx + "--max-weight must be positive");
  require(std::isfinite(opt.fade) && opt.fade > 0, ctx + "--fade must be positive");
  const DatasetManifest man = load_manifest(dir + "/manifest.json");
  require(man.rig_checksum == model.rig_checksum,
          dir + ": the dataset was made from rig '" + man.rig_name + "' (checksum " + hex64(man.rig_checksum) +
              "), the model belongs to '" + model.rig_name + "' (" + hex64(model.rig_checksum) + ")");
  require(man.num_lr_nodes == model.num_lr && man.num_surface == model.num_hr,
          dir + ": the dataset has " + std::to_string(man.num_lr_nodes) + " LR nodes and " +
              std::to_string(man.num_surface) + " surface vertices, the model " + std::to_string(model.num_lr) +
              " and " + std::to_string(model.num_hr));
  const double limit = std::min(opt.max_weight, opt.fade / 2);

  // Every single-shape training frame at a usable weight, one per weight.
  std::map<std::string, std::map<double, Sample>> found;
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
      if (!(w > 0 && w <= limit)) continue;
      auto& per_shape = found[s.header.weight_names[size_t(active)]];
      if (!per_shape.count(w)) per_shape[w] = {e.name, f, w, fr.lr_disp, fr.hr_disp, {}};
    }
  }
  require(!found.empty(), dir + ": no training frame has a single blendshape active at a weight in (0, " +
                              std::to_string(limit) + "] (--max-weight, and at most --fade / 2); add the built-in "
                              "\"nudge\" performance");

  SrModel net = model;
  net.rest_correctives = {};
  auto inference = make_cpu_inference(std::make_shared<const SrModel>(net));
  RestCorrectiveFit fit;
  RestCorrectives& t = fit.correctives;
  t.fade = opt.fade;
  t.ridge = opt.ridge;
  const size_t N3 = 3 * size_t(model.num_lr), M3 = 3 * size_t(model.num_hr);
  for (auto& [name, per_shape] : found) {
    t.shapes.push_back(name);
    t.amplitudes.emplace_back();
    const Sample& smallest = per_shape.begin()->second;
    for (size_t i = 0; i < N3; ++i) t.lr.push_back(float(smallest.lr[i] / smallest.weight));
    for (auto& [w, p] : per_shape) {
      p.predicted.resize(M3);
      inference->infer(p.lr.data(), p.predicted.data());
      t.amplitudes.back().push_back(float(w));
      // Divided by φ at the frame, so that the corrected model reproduces it.
      const double phi = rest_fade(w, opt.fade);
      for (size_t i = 0; i < M3; ++i) t.hr.push_back(float((p.hr[i] - p.predicted[i]) / phi));
    }
  }
  validate_rest_correctives(t, model.num_lr, model.num_hr, dir);
  const RestCorrection correction(t, model.num_lr, model.num_hr);
  for (const auto& [name, per_shape] : found) {
    nlohmann::json samples = nlohmann::json::array();
    for (const auto& [w, p] : per_shape) {
      std::vector<float> corrected = p.predicted;
      correction.apply(p.lr.data(), corrected.data());
      samples.push_back({{"sequence", p.sequence},
                         {"frame", p.frame},
                         {"weight", w},
                         {"network_error_cm", mean_error_cm(p.predicted, p.hr)},
                         {"corrected_error_cm", mean_error_cm(corrected, p.hr)}});
    }
    fit.shapes.push_back({{"shape", name}, {"samples", samples}});
  }
  for (const auto& n : man.weight_names)
    if (!found.count(n)) fit.unmeasured.push_back(n);
  return fit;
}

}  // namespace facesr
