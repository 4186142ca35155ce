#include "sr_fixtures.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "rig/rig_io.h"
#include "sr/sr_geometry.h"
#include "test_support.h"
#include "train/model_export.h"
#include "train/sr_network.h"

namespace facesr::fixtures {

std::shared_ptr<SrModel> random_model(bool fe, bool cu, uint64_t seed, bool skip, bool zero_rest,
                                      std::vector<int> recon_hidden) {
  const Rig& rig = procedural_rig();
  auto m = std::make_shared<SrModel>();
  m->arch.feature_encoding = fe;
  m->arch.coordinate_upsampling = cu;
  m->arch.embedded_skip = skip;
  m->arch.zero_rest = zero_rest;
  m->arch.recon_hidden = std::move(recon_hidden);
  m->rig_name = rig.name;
  m->rig_checksum = rig_checksum(rig);
  m->geometry = build_sr_geometry(rig);
  m->num_lr = m->geometry.num_lr;
  m->num_hr = m->geometry.num_hr;
  m->arch.input_scale = 0.2;
  m->arch.output_scale = 0.3;
  set_coordinate_frame(m->arch, m->geometry);
  torch::manual_seed(seed);
  SrNetwork net(m->arch, m->geometry);
  if (!cu) {
    torch::NoGradGuard ng;
    net->named_parameters().find("free_weights")->normal_();
  }
  export_parameters(*net, *m);
  return m;
}

torch::Tensor lr_frames(const SrModel& m, int F) {
  const auto x = torch::from_blob(const_cast<float*>(m.geometry.lr_rest.data()), {m.num_lr, 3}).clone();
  std::vector<torch::Tensor> out;
  for (int f = 0; f < F; ++f)
    out.push_back(0.3 * torch::sin(x * (0.4 + 0.1 * f) + f) + 0.02 * torch::randn({m.num_lr, 3}));
  return torch::stack(out);
}

std::vector<float> random_values(size_t n, uint32_t seed, float scale) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0f, scale);
  std::vector<float> v(n);
  for (float& x : v) x = g(rng);
  return v;
}

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, double(std::abs(a[i] - b[i])));
  return d;
}

}  // namespace facesr::fixtures
