#include "train/training_data.h"

#include "core/error.h"
#include "core/framed_file.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"

namespace facesr {

namespace {

struct Builder {
  std::vector<float> lr, hr, emb;
  FrameSet set;
  void add(const DatasetFrame& f, const std::string& seq, int index) {
    lr.insert(lr.end(), f.lr_disp.begin(), f.lr_disp.end());
    hr.insert(hr.end(), f.hr_disp.begin(), f.hr_disp.end());
    emb.insert(emb.end(), f.embedded_disp.begin(), f.embedded_disp.end());
    set.sequence.push_back(seq);
    set.frame.push_back(index);
    set.weights.push_back(f.weights);
    set.jaw.push_back(f.jaw);
  }
  FrameSet finish(int64_t N, int64_t M) {
    const int64_t F = int64_t(set.frame.size());
    set.lr = torch::from_blob(lr.data(), {F, N, 3}, torch::kFloat32).clone();
    set.hr = torch::from_blob(hr.data(), {F, M, 3}, torch::kFloat32).clone();
    set.embedded = torch::from_blob(emb.data(), {F, M, 3}, torch::kFloat32).clone();
    return std::move(set);
  }
};

}  // namespace

DatasetSplit load_dataset_split(const std::string& dir, uint64_t rig_checksum, int validation_every,
                                bool require_train, bool keep_capped) {
  const DatasetManifest m = load_manifest(dir + "/manifest.json");
  require(m.rig_checksum == rig_checksum, dir + ": the dataset was made from rig '" + m.rig_name + "' (checksum " +
                                              hex64(m.rig_checksum) + "), not from this rig (checksum " +
                                              hex64(rig_checksum) + ")");
  Builder train, val, test;
  const double hr_tol = m.extra.is_object() && m.extra.contains("hr_newton_tol") && m.extra["hr_newton_tol"].is_number()
                            ? m.extra["hr_newton_tol"].get<double>()
                            : 1e-3;
  int capped = 0;
  for (const auto& e : m.sequences) {
    require(e.complete, dir + ": sequence '" + e.name + "' is not complete; finish it with `facesr dataset`");
    const DatasetSequence s = read_dataset_sequence(dir + "/" + e.file);
    require(int(s.header.num_lr_nodes) == m.num_lr_nodes && int(s.header.num_surface) == m.num_surface,
            dir + "/" + e.file + ": its sizes differ from the manifest's");
    for (int f = 0; f < s.num_frames(); ++f) {
      const bool is_val = is_validation_frame(f, validation_every);
      Builder& b = e.split == "test" ? test : is_val ? val : train;
      const DatasetFrame fr = s.frame(f);
      if (&b != &test && !keep_capped && fr.stats.hr_rel_residual > hr_tol) {
        ++capped;
        continue;
      }
      b.add(fr, e.name, f);
    }
  }
  require(!require_train || !train.set.frame.empty(), dir + ": no training frames (no sequence has split \"train\")");
  DatasetSplit out;
  out.num_lr = m.num_lr_nodes;
  out.num_hr = m.num_surface;
  out.capped_left_out = capped;
  out.weight_names = m.weight_names;
  if (!train.set.frame.empty()) out.train = train.finish(m.num_lr_nodes, m.num_surface);
  if (!val.set.frame.empty()) out.validation = val.finish(m.num_lr_nodes, m.num_surface);
  if (!test.set.frame.empty()) out.test = test.finish(m.num_lr_nodes, m.num_surface);
  return out;
}

}  // namespace facesr
