// Rest tangents (sr/rest_tangents.h): the correction's arithmetic, its
// model-file round trip, parity of every inference path with it, and the fit
// (`facesr model tangents`) on a small dataset whose HR response is linear
// in the weights, so the first-order claim can be checked exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include <nlohmann/json.hpp>

#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "rig/rig_io.h"
#include "runtime/sr_inference.h"
#include "sr/rest_tangents.h"
#include "sr/sr_model.h"
#include "sr/sr_model_blend.h"
#include "sr_fixtures.h"
#include "test_support.h"
#include "train/torch_predictor.h"

namespace facesr {
namespace {

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

namespace fs = std::filesystem;
using fixtures::error_of;

std::vector<float> random_values(size_t n, uint32_t seed, float scale) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0.0f, scale);
  std::vector<float> v(n);
  for (float& x : v) x = g(rng);
  return v;
}

RestTangents two_shapes(int N, int M, uint32_t seed) {
  RestTangents t;
  t.shapes = {"a", "b"};
  t.amplitudes = {0.005f, 0.02f};
  t.lr = random_values(2 * 3 * size_t(N), seed, 1.0f);
  t.hr = random_values(2 * 3 * size_t(M), seed + 1, 0.5f);
  return t;
}

std::vector<float> combine(const RestTangents& t, double a, double b, int N) {
  std::vector<float> x(3 * size_t(N));
  for (size_t i = 0; i < x.size(); ++i) x[i] = float(a * t.lr[i] + b * t.lr[x.size() + i]);
  return x;
}

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, double(std::abs(a[i] - b[i])));
  return d;
}

TEST(RestTangents, CoefficientsRecoverTheWeightsOfACombination) {
  const int N = 40, M = 7;
  const RestTangents t = two_shapes(N, M, 5);
  const RestTangentCorrection corr(t, N, M);
  const auto c = corr.coefficients(combine(t, 0.03, -0.01, N).data());
  // The ridge shrinks by about ridge / (1 + ridge) for directions this size.
  EXPECT_NEAR(c[0], 0.03, 0.03 * 3e-3);
  EXPECT_NEAR(c[1], -0.01, 0.01 * 3e-3);
  const auto zero = corr.coefficients(std::vector<float>(3 * N, 0.0f).data());
  EXPECT_EQ(zero[0], 0.0);
  EXPECT_EQ(zero[1], 0.0);
}

// The added field is φ(‖c‖) Σ c_s r_s: zero at rest, r_a · ε + O(ε⁵) along
// shape a (φ is flat: 1 − O(ε⁴)), and gone for large poses.
TEST(RestTangents, CorrectionIsFirstOrderExactAndFadesForLargePoses) {
  const int N = 40, M = 7;
  const RestTangents t = two_shapes(N, M, 9);
  const RestTangentCorrection corr(t, N, M);
  auto added = [&](double a, double b) {
    std::vector<float> y(3 * size_t(M), 0.0f);
    corr.apply(combine(t, a, b, N).data(), y.data());
    return y;
  };
  for (float v : added(0, 0)) EXPECT_EQ(v, 0.0f);
  // Relative to the ridge's own shrink, measured at the smallest ε.
  const std::vector<float> tiny = added(1e-4, 0);
  double shrink = 0;
  for (size_t i = 0; i < tiny.size(); ++i) shrink = std::max(shrink, std::abs(tiny[i] / 1e-4 - t.hr[i]));
  EXPECT_LT(shrink, 5e-3 * 2.0) << "the ridge should shrink a well-conditioned direction by about 1e-3";
  double prev = -1;
  for (double eps : {0.02, 0.01, 0.005}) {
    const std::vector<float> y = added(eps, 0);
    double err = 0;  // beyond the ridge's linear shrink
    for (size_t i = 0; i < y.size(); ++i)
      err = std::max(err, std::abs(double(y[i]) - eps * double(tiny[i]) / 1e-4));
    if (prev > 0) EXPECT_GT(prev / err, 20.0) << "eps " << eps << ": the remainder should fall like eps^5 (32x)";
    prev = err;
  }
  // fade = 0.05: at ‖c‖ = 1 the factor is e^-160000.
  for (float v : added(1.0, 0.5)) EXPECT_EQ(v, 0.0f);
}

TEST(RestTangents, ValidationNamesTheProblem) {
  const int N = 10, M = 4;
  RestTangents t = two_shapes(N, M, 1);
  validate_rest_tangents(t, N, M, "x");
  RestTangents bad = t;
  bad.hr.pop_back();
  EXPECT_HAS(error_of([&] { validate_rest_tangents(bad, N, M, "x"); }), "HR residuals have");
  bad = t;
  bad.shapes[1] = "a";
  EXPECT_HAS(error_of([&] { validate_rest_tangents(bad, N, M, "x"); }), "repeated");
  bad = t;
  bad.lr[3] = std::nanf("");
  EXPECT_HAS(error_of([&] { validate_rest_tangents(bad, N, M, "x"); }), "not finite");
  bad = t;
  bad.fade = 0;
  EXPECT_HAS(error_of([&] { validate_rest_tangents(bad, N, M, "x"); }), "fade");
}

class RestTangentModels : public fixtures::ScratchSuite<RestTangentModels> {
 public:
  static constexpr const char* kScratch = "facesr_rest_tangents_";
};

std::shared_ptr<SrModel> model_with_tangents(uint32_t seed) {
  auto m = fixtures::random_model(true, true, seed, true, true);
  m->rest_tangents = two_shapes(m->num_lr, m->num_hr, seed);
  return m;
}

TEST_F(RestTangentModels, ModelFileRoundTripsTheTangentsAndRefusesBadOnes) {
  const auto m = model_with_tangents(31);
  m->rest_tangents.fade = 0.07;
  save_sr_model(path("t.fsm"), *m);
  const SrModel r = load_sr_model(path("t.fsm"));
  EXPECT_EQ(r.rest_tangents.shapes, m->rest_tangents.shapes);
  EXPECT_EQ(r.rest_tangents.amplitudes, m->rest_tangents.amplitudes);
  EXPECT_EQ(r.rest_tangents.lr, m->rest_tangents.lr);
  EXPECT_EQ(r.rest_tangents.hr, m->rest_tangents.hr);
  EXPECT_EQ(r.rest_tangents.fade, 0.07);
  // Without tangents the file has none (and version-2 files, such as the
  // shipped procedural model, still load: test_model_cli).
  auto plain = *m;
  plain.rest_tangents = {};
  save_sr_model(path("plain.fsm"), plain);
  EXPECT_TRUE(load_sr_model(path("plain.fsm")).rest_tangents.empty());

  auto bad = *m;
  bad.rest_tangents.lr.resize(5);
  EXPECT_HAS(error_of([&] { save_sr_model(path("bad.fsm"), bad); }), "LR directions have 5 values");
  EXPECT_FALSE(fs::exists(path("bad.fsm")));
  // A blend is another network: its tangents must be measured again.
  EXPECT_HAS(error_of([&] { blend_sr_models(*m, plain, 0.5, "blend"); }), "fit them again");
}

// LibTorch, the C++ reference and the OpenCL kernels give the same corrected
// output, and it differs from the network alone by the correction.
TEST_F(RestTangentModels, EveryInferencePathAddsTheSameCorrection) {
  const auto m = model_with_tangents(41);
  auto plain = std::make_shared<SrModel>(*m);
  plain->rest_tangents = {};
  const RestTangentCorrection corr(m->rest_tangents, m->num_lr, m->num_hr);
  const auto& t = m->rest_tangents;
  const int N = m->num_lr, M = m->num_hr;
  auto cpu = make_cpu_inference(m), cpu_plain = make_cpu_inference(plain), cl = make_cl_inference(m);
  TorchPredictor torch_pred(*m);
  for (double a : {0.004, 0.02}) {
    const std::vector<float> x = combine(t, a, 0.5 * a, N);
    std::vector<float> y_cpu(3 * size_t(M)), y_plain(3 * size_t(M)), y_cl(3 * size_t(M));
    cpu->infer(x.data(), y_cpu.data());
    cpu_plain->infer(x.data(), y_plain.data());
    cl->infer(x.data(), y_cl.data());
    const auto ref = torch_pred.predict(torch::from_blob(const_cast<float*>(x.data()), {1, N, 3}).clone());
    const std::vector<float> y_torch(ref.data_ptr<float>(), ref.data_ptr<float>() + 3 * size_t(M));
    EXPECT_LT(max_abs_diff(y_cpu, y_torch), 1e-4) << a;
    EXPECT_LT(max_abs_diff(y_cl, y_torch), 1e-4) << a;
    std::vector<float> expected = y_plain;
    corr.apply(x.data(), expected.data());
    EXPECT_LT(max_abs_diff(y_cpu, expected), 1e-6) << a;
    EXPECT_GT(max_abs_diff(y_cpu, y_plain), 1e-3) << a << ": the correction should be visible";
  }
  // Profiled runs time it as a stage of its own.
  ClInferenceOptions o;
  o.profile = true;
  auto profiled = make_cl_inference(m, o);
  std::vector<float> x(3 * size_t(N), 0.0f), y(3 * size_t(M));
  profiled->infer(x.data(), y.data());
  const auto p = profiled->last_profile();
  ASSERT_FALSE(p.empty());
  EXPECT_EQ(p.back().first, "rest tangents");
  EXPECT_GE(p.back().second, 0.0);
}

// A dataset on the procedural rig with three shapes: LR displacement and HR
// target are linear in the weights (d_s, t_s per unit weight), so after the
// fit the corrected model matches the target to first order, also on frames
// the fit never saw.
class RestTangentFitCli : public fixtures::ScratchSuite<RestTangentFitCli> {
 public:
  static constexpr const char* kScratch = "facesr_rest_tangent_fit_";

 protected:
  static void SetUpTestSuite() {
    ScratchSuite::SetUpTestSuite();
    model_ = fixtures::random_model(true, true, 51, true, true);
    save_sr_model(path("m.fsm"), *model_);
    const int N = model_->num_lr, M = model_->num_hr;
    for (int s = 0; s < 3; ++s) {
      // Frame s of lr_frames: its own frequency and phase, so the three
      // directions are far from parallel. A few cm per unit weight.
      const auto d = (fixtures::lr_frames(*model_, s + 1)[s] * (3.0 + s)).contiguous();
      d_.emplace_back(d.data_ptr<float>(), d.data_ptr<float>() + 3 * N);
      t_.push_back(random_values(3 * size_t(M), 60 + s, 1.0f));
    }
    // Frame 2 (A at 0.005) must be chosen over frame 1 (0.02) and frame 9,
    // which is smaller but held out for validation; B only at frame 3; C
    // only above --max-weight; frame 4 has two shapes.
    const std::vector<std::array<float, 3>> train = {{0, 0, 0},    {0.02f, 0, 0}, {0.005f, 0, 0}, {0, 0.02f, 0},
                                                     {0.01f, 0.01f, 0}, {0, 0, 0.5f}, {0.05f, 0, 0}, {0, 0.08f, 0},
                                                     {0, 0, 0},    {0.001f, 0, 0}, {0, 0.04f, 0}, {0, 0, 0}};
    write_sequence("nudge", train);
    write_sequence("held", {{0.01f, 0.015f, 0}, {0.003f, 0, 0}});
    DatasetManifest man;
    man.rig_name = model_->rig_name;
    man.rig_checksum = model_->rig_checksum;
    man.num_lr_nodes = N;
    man.num_surface = M;
    man.weight_names = {"shapeA", "shapeB", "shapeC"};
    for (const char* name : {"nudge", "held"}) {
      DatasetManifest::Entry e;
      e.name = name;
      e.file = std::string(name) + ".fsd";
      e.frames = name == std::string("nudge") ? 12 : 2;
      e.split = name == std::string("nudge") ? "train" : "test";
      e.complete = true;
      man.sequences.push_back(e);
    }
    fs::create_directories(path("data"));
    save_manifest(path("data/manifest.json"), man);
  }

  static DatasetFrame frame(const std::array<float, 3>& w, double time) {
    const int N = model_->num_lr, M = model_->num_hr;
    DatasetFrame f;
    f.time = time;
    f.weights.assign(w.begin(), w.end());
    f.jaw = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    f.lr_disp.assign(3 * size_t(N), 0.0f);
    f.hr_disp.assign(3 * size_t(M), 0.0f);
    f.embedded_disp.assign(3 * size_t(M), 0.0f);
    for (int s = 0; s < 3; ++s) {
      for (size_t i = 0; i < f.lr_disp.size(); ++i) f.lr_disp[i] += w[s] * d_[s][i];
      for (size_t i = 0; i < f.hr_disp.size(); ++i) f.hr_disp[i] += w[s] * t_[s][i];
    }
    return f;
  }

  static void write_sequence(const std::string& name, const std::vector<std::array<float, 3>>& weights) {
    DatasetSequence seq;
    seq.header.name = name;
    seq.header.rig_checksum = model_->rig_checksum;
    seq.header.num_lr_nodes = uint64_t(model_->num_lr);
    seq.header.num_surface = uint64_t(model_->num_hr);
    seq.header.weight_names = {"shapeA", "shapeB", "shapeC"};
    for (size_t f = 0; f < weights.size(); ++f) seq.frames.push_back(frame(weights[f], double(f) / 30));
    fs::create_directories(path("data"));
    write_dataset_sequence(path("data/" + name + ".fsd"), seq);
  }

  // Mean per-vertex error (cm) of a model on the frame with these weights.
  static double error_cm(const SrModel& m, const std::array<float, 3>& w) {
    const DatasetFrame f = frame(w, 0);
    const auto y = TorchPredictor(m).predict(
        torch::from_blob(const_cast<float*>(f.lr_disp.data()), {1, m.num_lr, 3}).clone());
    const auto target = torch::from_blob(const_cast<float*>(f.hr_disp.data()), {m.num_hr, 3});
    return (y[0] - target).norm(2, 1).mean().item<double>();
  }

  static inline std::shared_ptr<SrModel> model_;
  static inline std::vector<std::vector<float>> d_, t_;
};

TEST_F(RestTangentFitCli, FitsOnTrainingFramesAndCorrectsNearRestPosesToFirstOrder) {
  const auto r = run("model tangents " + q("m.fsm") + " --dataset " + q("data") + " -o " + q("t.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("rest_tangents").get<int>(), 2);
  EXPECT_EQ(j.at("unmeasured"), nlohmann::json::array({"shapeC"}));
  const auto& shapes = j.at("shapes");
  ASSERT_EQ(shapes.size(), 2u);
  EXPECT_EQ(shapes[0].at("shape"), "shapeA");
  EXPECT_EQ(shapes[0].at("frame").get<int>(), 2) << "the smallest weight not held out for validation";
  EXPECT_EQ(shapes[1].at("shape"), "shapeB");
  EXPECT_EQ(shapes[1].at("frame").get<int>(), 3);
  for (const auto& s : shapes)
    EXPECT_LT(s.at("corrected_error_cm").get<double>(), 0.03 * s.at("network_error_cm").get<double>()) << s;

  const SrModel m = load_sr_model(path("t.fsm"));
  ASSERT_EQ(m.rest_tangents.count(), 2);
  EXPECT_EQ(m.training.at("rest_tangents").at("shapes").size(), 2u);
  // Frames the fit did not use: a combination, the held-out weight, the test split's.
  for (const std::array<float, 3>& w : std::vector<std::array<float, 3>>{
           {0.01f, 0.01f, 0}, {0.001f, 0, 0}, {0.003f, 0, 0}, {0, 0.006f, 0}}) {
    const double before = error_cm(*model_, w), after = error_cm(m, w);
    EXPECT_LT(after, 0.15 * before) << w[0] << ", " << w[1] << ": " << before << " -> " << after << " cm";
  }
  // Large poses are the network's alone.
  EXPECT_NEAR(error_cm(m, {0.6f, 0.3f, 0}), error_cm(*model_, {0.6f, 0.3f, 0}), 1e-6);
}

TEST_F(RestTangentFitCli, BadInputFailsWithAMessageAndNoOutput) {
  auto r = run("model tangents " + q("m.fsm") + " --dataset " + q("data") + " --max-weight 0.0001 -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "no training frame has a single blendshape");
  EXPECT_FALSE(fs::exists(path("x.fsm")));

  SrModel other = *model_;
  other.rig_checksum ^= 1;
  save_sr_model(path("other.fsm"), other);
  r = run("model tangents " + q("other.fsm") + " --dataset " + q("data") + " -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "the dataset was made from rig");
  EXPECT_FALSE(fs::exists(path("x.fsm")));

  r = run("model tangents " + q("m.fsm") + " --dataset " + q("nowhere") + " -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "manifest.json");
  EXPECT_FALSE(fs::exists(path("x.fsm")));
}

}  // namespace
}  // namespace facesr
