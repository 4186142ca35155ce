// Near-rest correctives (sr/rest_correctives.h): the correction's
// arithmetic (coefficients, first order at rest, in-betweens, fade), its
// model-file round trip, parity of every inference path with it, and the fit
// (`facesr model correctives`) on a small dataset whose HR response is
// linear in the weights, so what it reproduces can be checked exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/checksum.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "rig/rig_io.h"
#include "runtime/sr_inference.h"
#include "sr/rest_correctives.h"
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
using fixtures::max_abs_diff;
using fixtures::random_values;

// Two shapes, one sample each at weight 0.05 (linear up to there).
RestCorrectives two_shapes(int N, int M, uint32_t seed) {
  RestCorrectives t;
  t.shapes = {"a", "b"};
  t.amplitudes = {{0.05f}, {0.05f}};
  t.lr = random_values(2 * 3 * size_t(N), seed, 1.0f);
  t.hr = random_values(2 * 3 * size_t(M), seed + 1, 0.5f);
  return t;
}

std::vector<float> combine(const RestCorrectives& t, double a, double b, int N) {
  std::vector<float> x(3 * size_t(N));
  for (size_t i = 0; i < x.size(); ++i) x[i] = float(a * t.lr[i] + b * t.lr[x.size() + i]);
  return x;
}

TEST(RestCorrectives, CoefficientsRecoverTheWeightsOfACombination) {
  const int N = 40, M = 7;
  const RestCorrectives t = two_shapes(N, M, 5);
  const RestCorrection corr(t, N, M);
  const auto c = corr.coefficients(combine(t, 0.03, -0.01, N).data());
  // The ridge shrinks by about ridge / (1 + ridge) for directions this size.
  EXPECT_NEAR(c[0], 0.03, 0.03 * 3e-3);
  EXPECT_NEAR(c[1], -0.01, 0.01 * 3e-3);
  const auto zero = corr.coefficients(std::vector<float>(3 * N, 0.0f).data());
  EXPECT_EQ(zero[0], 0.0);
  EXPECT_EQ(zero[1], 0.0);
}

// Below the first sample the added field is φ(‖c‖) Σ (c_s / a_s1) R_s1:
// zero at rest, (R_a / a_a1) · ε + O(ε⁵) along shape a (φ is flat:
// 1 − O(ε⁴)), and gone for large poses.
TEST(RestCorrectives, CorrectionIsFirstOrderExactAndFadesForLargePoses) {
  const int N = 40, M = 7;
  const RestCorrectives t = two_shapes(N, M, 9);
  const RestCorrection corr(t, N, M);
  auto added = [&](double a, double b) {
    std::vector<float> y(3 * size_t(M), 0.0f);
    corr.apply(combine(t, a, b, N).data(), y.data());
    return y;
  };
  for (float v : added(0, 0)) EXPECT_EQ(v, 0.0f);
  // Relative to the ridge's own shrink, measured at the smallest ε.
  const std::vector<float> tiny = added(1e-4, 0);
  double shrink = 0;
  for (size_t i = 0; i < tiny.size(); ++i) shrink = std::max(shrink, std::abs(tiny[i] / 1e-4 - t.hr[i] / 0.05));
  EXPECT_LT(shrink, 1e-2 * 20) << "the ridge should shrink a well-conditioned direction by about 1e-3 (R/a is ~20)";
  double prev = -1;
  for (double eps : {0.02, 0.01, 0.005}) {
    const std::vector<float> y = added(eps, 0);
    double err = 0;  // beyond the ridge's linear shrink
    for (size_t i = 0; i < y.size(); ++i)
      err = std::max(err, std::abs(double(y[i]) - eps * double(tiny[i]) / 1e-4));
    if (prev > 0) EXPECT_GT(prev / err, 20.0) << "eps " << eps << ": the remainder should fall like eps^5 (32x)";
    prev = err;
  }
  // fade = 0.2: at ‖c‖ = 1.1 the factor is e^-915.
  for (float v : added(1.0, 0.5)) EXPECT_EQ(v, 0.0f);
}

// One shape with samples at 0.01 and 0.04: through (0, 0), (a_k, R_k),
// linear between them, held beyond the last, the first segment's line
// below 0; all times φ(|c|).
TEST(RestCorrectives, InBetweensInterpolateAndNeverExtrapolate) {
  const int N = 30, M = 5;
  RestCorrectives t;
  t.shapes = {"s"};
  t.amplitudes = {{0.01f, 0.04f}};
  t.lr = random_values(3 * size_t(N), 3, 1.0f);
  t.hr = random_values(2 * 3 * size_t(M), 4, 0.5f);
  const RestCorrection corr(t, N, M);
  const size_t M3 = 3 * size_t(M);
  for (double w : {-0.005, 0.005, 0.01, 0.025, 0.04, 0.06, 0.3}) {
    std::vector<float> x(3 * size_t(N)), y(M3, 0.0f);
    for (size_t i = 0; i < x.size(); ++i) x[i] = float(w * t.lr[i]);
    const double v = corr.coefficients(x.data())[0];
    EXPECT_NEAR(v, w, std::abs(w) * 2e-3 + 1e-9);
    corr.apply(x.data(), y.data());
    const double phi = rest_fade(std::abs(v), t.fade);
    double r1 = 0, r2 = 0;  // weights of R_1 and R_2
    if (v <= 0.01) r1 = v / 0.01;
    else if (v >= 0.04) r2 = 1;
    else r1 = (0.04 - v) / 0.03, r2 = (v - 0.01) / 0.03;
    double worst = 0;
    for (size_t i = 0; i < M3; ++i)
      worst = std::max(worst, std::abs(y[i] - phi * (r1 * t.hr[i] + r2 * t.hr[M3 + i])));
    EXPECT_LT(worst, 1e-5) << "w = " << w;
  }
}

TEST(RestCorrectives, ValidationNamesTheProblem) {
  const int N = 10, M = 4;
  RestCorrectives t = two_shapes(N, M, 1);
  validate_rest_correctives(t, N, M, "x");
  RestCorrectives bad = t;
  bad.hr.pop_back();
  EXPECT_HAS(error_of([&] { validate_rest_correctives(bad, N, M, "x"); }), "HR residuals have");
  bad = t;
  bad.shapes[1] = "a";
  EXPECT_HAS(error_of([&] { validate_rest_correctives(bad, N, M, "x"); }), "repeated");
  bad = t;
  bad.lr[3] = std::nanf("");
  EXPECT_HAS(error_of([&] { validate_rest_correctives(bad, N, M, "x"); }), "not finite");
  bad = t;
  bad.fade = 0;
  EXPECT_HAS(error_of([&] { validate_rest_correctives(bad, N, M, "x"); }), "fade");
  bad = t;
  bad.amplitudes[0] = {0.02f, 0.01f};
  EXPECT_HAS(error_of([&] { validate_rest_correctives(bad, N, M, "x"); }), "positive and increasing");
}

class RestCorrectiveModels : public fixtures::ScratchSuite<RestCorrectiveModels> {
 public:
  static constexpr const char* kScratch = "facesr_rest_correctives_";
};

std::shared_ptr<SrModel> model_with_correctives(uint32_t seed) {
  auto m = fixtures::random_model(true, true, seed, true, true);
  m->rest_correctives = two_shapes(m->num_lr, m->num_hr, seed);
  return m;
}

TEST_F(RestCorrectiveModels, ModelFileRoundTripsTheCorrectivesAndRefusesBadOnes) {
  const auto m = model_with_correctives(31);
  m->rest_correctives.fade = 0.07;
  m->rest_correctives.amplitudes[1] = {0.01f, 0.05f};  // two samples: one more residual field
  const auto extra = random_values(3 * size_t(m->num_hr), 7, 0.5f);
  m->rest_correctives.hr.insert(m->rest_correctives.hr.end(), extra.begin(), extra.end());
  save_sr_model(path("t.fsm"), *m);
  const SrModel r = load_sr_model(path("t.fsm"));
  EXPECT_EQ(r.rest_correctives.shapes, m->rest_correctives.shapes);
  EXPECT_EQ(r.rest_correctives.amplitudes, m->rest_correctives.amplitudes);
  EXPECT_EQ(r.rest_correctives.lr, m->rest_correctives.lr);
  EXPECT_EQ(r.rest_correctives.hr, m->rest_correctives.hr);
  EXPECT_EQ(r.rest_correctives.fade, 0.07);
  EXPECT_EQ(r.rest_correctives.samples(), 3);
  // Without correctives the file has none (and version-2 files, such as the
  // shipped procedural model, still load: test_model_cli).
  auto plain = *m;
  plain.rest_correctives = {};
  save_sr_model(path("plain.fsm"), plain);
  EXPECT_TRUE(load_sr_model(path("plain.fsm")).rest_correctives.empty());

  // A version-3 file (correctives in an earlier form) is refused by name,
  // even with a valid checksum; version 2 is read.
  for (uint32_t version : {3u, 2u}) {
    std::string bytes = fixtures::read_text(path("plain.fsm"));
    std::memcpy(&bytes[8], &version, 4);
    if (version == 2) bytes.erase(bytes.size() - 24, 16);  // no corrective arrays (two empty vectors)
    const uint64_t sum = fnv1a64(bytes.data(), bytes.size() - 8);
    std::memcpy(&bytes[bytes.size() - 8], &sum, 8);
    std::ofstream(path("v.fsm"), std::ios::binary) << bytes;
    if (version == 3)
      EXPECT_HAS(error_of([&] { load_sr_model(path("v.fsm")); }), "model format version 3 is not supported");
    else
      EXPECT_TRUE(load_sr_model(path("v.fsm")).rest_correctives.empty());
  }

  auto bad = *m;
  bad.rest_correctives.lr.resize(5);
  EXPECT_HAS(error_of([&] { save_sr_model(path("bad.fsm"), bad); }), "LR directions have 5 values");
  EXPECT_FALSE(fs::exists(path("bad.fsm")));
  // A blend is another network: its correctives must be measured again.
  EXPECT_HAS(error_of([&] { blend_sr_models(*m, plain, 0.5, "blend"); }), "fit them again");
}

// LibTorch, the C++ reference and the OpenCL kernels give the same corrected
// output, and it differs from the network alone by the correction.
TEST_F(RestCorrectiveModels, EveryInferencePathAddsTheSameCorrection) {
  const auto m = model_with_correctives(41);
  auto plain = std::make_shared<SrModel>(*m);
  plain->rest_correctives = {};
  const RestCorrection corr(m->rest_correctives, m->num_lr, m->num_hr);
  const auto& t = m->rest_correctives;
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
  EXPECT_EQ(p.back().first, "rest correctives");
  EXPECT_GE(p.back().second, 0.0);
}

// A dataset on the procedural rig with three shapes: LR displacement and HR
// target are linear in the weights (d_s, t_s per unit weight), so after the
// fit the corrected model matches the target to first order, also on frames
// the fit never saw.
class RestCorrectiveFitCli : public fixtures::ScratchSuite<RestCorrectiveFitCli> {
 public:
  static constexpr const char* kScratch = "facesr_rest_corrective_fit_";

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

TEST_F(RestCorrectiveFitCli, FitsOnTrainingFramesAndReproducesWhatItMeasured) {
  const auto r =
      run("model correctives " + q("m.fsm") + " --dataset " + q("data") + " -o " + q("t.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("rest_correctives").get<int>(), 2);
  EXPECT_EQ(j.at("samples").get<int>(), 6);
  EXPECT_EQ(j.at("unmeasured"), nlohmann::json::array({"shapeC"}));
  const auto& shapes = j.at("shapes");
  ASSERT_EQ(shapes.size(), 2u);
  // By weight; frame 9 (A at 0.001) is held out for validation, frame 4 has
  // two shapes, frame 5 (C at 0.5) is above --max-weight.
  const std::vector<std::pair<std::string, std::vector<int>>> expected = {{"shapeA", {2, 1, 6}},
                                                                          {"shapeB", {3, 10, 7}}};
  for (size_t s = 0; s < 2; ++s) {
    EXPECT_EQ(shapes[s].at("shape"), expected[s].first);
    const auto& samples = shapes[s].at("samples");
    ASSERT_EQ(samples.size(), 3u) << shapes[s];
    for (size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(samples[k].at("frame").get<int>(), expected[s].second[k]) << samples[k];
      EXPECT_LT(samples[k].at("corrected_error_cm").get<double>(),
                0.03 * samples[k].at("network_error_cm").get<double>())
          << samples[k];
    }
  }

  const SrModel m = load_sr_model(path("t.fsm"));
  ASSERT_EQ(m.rest_correctives.count(), 2);
  EXPECT_EQ(m.training.at("rest_correctives").at("shapes").size(), 2u);
  // Frames the fit did not use: a combination, the held-out weight, the
  // test split's, below B's first sample, between A's samples.
  for (const std::array<float, 3>& w : std::vector<std::array<float, 3>>{
           {0.01f, 0.01f, 0}, {0.001f, 0, 0}, {0.003f, 0, 0}, {0, 0.006f, 0}, {0.03f, 0, 0}}) {
    const double before = error_cm(*model_, w), after = error_cm(m, w);
    EXPECT_LT(after, 0.15 * before) << w[0] << ", " << w[1] << ": " << before << " -> " << after << " cm";
  }
  // Large poses are the network's alone.
  EXPECT_NEAR(error_cm(m, {0.6f, 0.3f, 0}), error_cm(*model_, {0.6f, 0.3f, 0}), 1e-6);
}

TEST_F(RestCorrectiveFitCli, BadInputFailsWithAMessageAndNoOutput) {
  auto r = run("model correctives " + q("m.fsm") + " --dataset " + q("data") + " --max-weight 0.0001 -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "no training frame has a single blendshape");
  EXPECT_FALSE(fs::exists(path("x.fsm")));

  SrModel other = *model_;
  other.rig_checksum ^= 1;
  save_sr_model(path("other.fsm"), other);
  r = run("model correctives " + q("other.fsm") + " --dataset " + q("data") + " -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "the dataset was made from rig");
  EXPECT_FALSE(fs::exists(path("x.fsm")));

  r = run("model correctives " + q("m.fsm") + " --dataset " + q("nowhere") + " -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "manifest.json");
  EXPECT_FALSE(fs::exists(path("x.fsm")));
}

}  // namespace
}  // namespace facesr
