// Residual smoothing (sr/residual_smoothing.h): the filter against a dense
// reference operator, its maximum principle, its model-file round trip and
// validation, parity of every inference path with it, and `facesr model
// smooth`.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "core/checksum.h"
#include "runtime/sr_inference.h"
#include "sr/residual_smoothing.h"
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

// The embedded displacement of the surface (M × 3) for an LR displacement.
std::vector<float> embedded(const SrGeometry& g, const std::vector<float>& x) {
  std::vector<float> e(3 * size_t(g.num_hr), 0.0f);
  for (int v = 0; v < g.num_hr; ++v)
    for (int a = 0; a < 4; ++a)
      for (int d = 0; d < 3; ++d)
        e[3 * v + d] += g.embed_weights[4 * v + a] * x[3 * size_t(g.embed_nodes[4 * v + a]) + d];
  return e;
}

// Σ over surface edges of ‖r_i − r_j‖²: how rough a field is.
double roughness(const SrGeometry& g, const std::vector<float>& r) {
  double s = 0;
  for (size_t t = 0; t < g.hr_tris.size(); t += 3)
    for (int a = 0; a < 3; ++a) {
      const size_t i = size_t(g.hr_tris[t + a]), j = size_t(g.hr_tris[t + (a + 1) % 3]);
      for (int d = 0; d < 3; ++d) s += std::pow(double(r[3 * i + d]) - r[3 * j + d], 2);
    }
  return s;
}

TEST(ResidualSmoothing, MatchesTheDenseOperatorAroundTheEmbeddedSurface) {
  const auto m = fixtures::random_model(true, true, 3, true);
  const SrGeometry& g = m->geometry;
  const int N = g.num_lr, M = g.num_hr;
  // Reference: P = I − λ (I − D⁻¹A) from the triangles' edges, applied K times.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(M, M);
  for (size_t t = 0; t < g.hr_tris.size(); t += 3)
    for (int a = 0; a < 3; ++a) {
      const int i = g.hr_tris[t + a], j = g.hr_tris[t + (a + 1) % 3];
      A(i, j) = A(j, i) = 1;
    }
  const ResidualSmoothing s{0.5, 3};
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(M, M);
  for (int i = 0; i < M; ++i)
    P.row(i) += s.lambda * (A.row(i) / A.row(i).sum() - Eigen::MatrixXd::Identity(M, M).row(i));

  const auto x = random_values(3 * size_t(N), 1, 0.3f), y = random_values(3 * size_t(M), 2, 0.3f);
  const auto e = embedded(g, x);
  Eigen::MatrixXd r(M, 3);
  for (int v = 0; v < M; ++v)
    for (int d = 0; d < 3; ++d) r(v, d) = y[3 * v + d] - e[3 * v + d];
  for (int k = 0; k < s.iterations; ++k) r = P * r;
  std::vector<float> expected(3 * size_t(M));
  for (int v = 0; v < M; ++v)
    for (int d = 0; d < 3; ++d) expected[3 * v + d] = float(e[3 * v + d] + r(v, d));

  ResidualSmoother smoother(s, g);
  std::vector<float> out = y;
  smoother.apply(x.data(), out.data());
  EXPECT_LT(max_abs_diff(out, expected), 1e-5);
  EXPECT_GT(max_abs_diff(out, y), 0.05) << "the filter should change a random residual";

  // The embedded surface itself, and the embedded surface plus a constant
  // shift, pass unchanged.
  std::vector<float> shifted = e;
  for (int v = 0; v < M; ++v) shifted[3 * v + 1] += 0.25f;
  std::vector<float> out2 = shifted;
  smoother.apply(x.data(), out2.data());
  EXPECT_LT(max_abs_diff(out2, shifted), 1e-5);

  // Zero iterations leave the output alone.
  ResidualSmoother none({0.5, 0}, g);
  std::vector<float> out3 = y;
  none.apply(x.data(), out3.data());
  EXPECT_EQ(out3, y);
}

// Each step is a convex combination: the residual's largest component never
// grows (maximum principle) and its roughness falls step by step.
TEST(ResidualSmoothing, NeverAmplifiesAndSmoothsMoreWithEveryStep) {
  const auto m = fixtures::random_model(true, true, 5, true);
  const SrGeometry& g = m->geometry;
  // e = 0: the output is the residual.
  const std::vector<float> x(3 * size_t(g.num_lr), 0.0f);
  const auto y = random_values(3 * size_t(g.num_hr), 9, 1.0f);
  double prev_rough = roughness(g, y);
  float prev_max = 0;
  for (float v : y) prev_max = std::max(prev_max, std::abs(v));
  for (int k = 1; k <= 4; ++k) {
    for (double lambda : {0.25, 1.0}) {
      ResidualSmoother sm({lambda, k}, g);
      std::vector<float> out = y;
      sm.apply(x.data(), out.data());
      float mx = 0;
      for (float v : out) mx = std::max(mx, std::abs(v));
      EXPECT_LE(mx, prev_max * (1 + 1e-6f)) << "K " << k << ", lambda " << lambda;
      EXPECT_LT(roughness(g, out), roughness(g, y)) << "K " << k << ", lambda " << lambda;
    }
    ResidualSmoother sm({0.5, k}, g);
    std::vector<float> out = y;
    sm.apply(x.data(), out.data());
    const double rough = roughness(g, out);
    EXPECT_LT(rough, prev_rough) << "K " << k;
    prev_rough = rough;
  }
}

TEST(ResidualSmoothing, ValidationNamesTheProblem) {
  EXPECT_HAS(error_of([] { validate_residual_smoothing({0.0, 2}, "x"); }), "lambda must be in (0, 1]");
  EXPECT_HAS(error_of([] { validate_residual_smoothing({1.5, 2}, "x"); }), "lambda must be in (0, 1]");
  EXPECT_HAS(error_of([] { validate_residual_smoothing({std::nan(""), 2}, "x"); }), "lambda");
  EXPECT_HAS(error_of([] { validate_residual_smoothing({0.5, -1}, "x"); }), "iterations must be 0 to 64");
  EXPECT_HAS(error_of([] { validate_residual_smoothing({0.5, 65}, "x"); }), "iterations must be 0 to 64");
  EXPECT_HAS(error_of([] {
               residual_smoothing_from_json({{"operator", "cotan"}, {"lambda", 0.5}, {"iterations", 1}}, "f");
             }),
             "operator 'cotan' is not known");
  EXPECT_HAS(error_of([] {
               residual_smoothing_from_json({{"operator", "umbrella"}, {"lambda", 0.5}}, "f");
             }),
             "missing or mistyped field");
  const auto s = residual_smoothing_from_json(residual_smoothing_to_json({0.25, 3}), "f");
  EXPECT_EQ(s.lambda, 0.25);
  EXPECT_EQ(s.iterations, 3);
}

class ResidualSmoothingModels : public fixtures::ScratchSuite<ResidualSmoothingModels> {
 public:
  static constexpr const char* kScratch = "facesr_residual_smoothing_";
};

TEST_F(ResidualSmoothingModels, ModelFileRoundTripsItAndRefusesBadOnes) {
  auto m = *fixtures::random_model(true, true, 11, true, true);
  m.residual_smoothing = {0.25, 2};
  save_sr_model(path("s.fsm"), m);
  const SrModel r = load_sr_model(path("s.fsm"));
  EXPECT_EQ(r.residual_smoothing.lambda, 0.25);
  EXPECT_EQ(r.residual_smoothing.iterations, 2);

  // A version-4 file has no smoothing: its readers would ignore the entry,
  // which is why smoothing needed version 5.
  std::string bytes = fixtures::read_text(path("s.fsm"));
  const uint32_t v4 = 4;
  std::memcpy(&bytes[8], &v4, 4);
  const uint64_t sum = fnv1a64(bytes.data(), bytes.size() - 8);
  std::memcpy(&bytes[bytes.size() - 8], &sum, 8);
  std::ofstream(path("v4.fsm"), std::ios::binary) << bytes;
  EXPECT_TRUE(load_sr_model(path("v4.fsm")).residual_smoothing.empty());

  auto bad = m;
  bad.residual_smoothing.lambda = 2;
  EXPECT_HAS(error_of([&] { save_sr_model(path("bad.fsm"), bad); }), "lambda must be in (0, 1]");
  EXPECT_FALSE(fs::exists(path("bad.fsm")));
  bad = *fixtures::random_model(true, true, 11, false, true);  // no embedded skip
  bad.residual_smoothing = {0.5, 1};
  EXPECT_HAS(error_of([&] { save_sr_model(path("bad.fsm"), bad); }),
             "needs the super-resolution network with the embedded skip");
  EXPECT_FALSE(fs::exists(path("bad.fsm")));
  // Blending keeps one smoothing, so both models must have the same.
  auto other = m;
  other.residual_smoothing = {};
  EXPECT_HAS(error_of([&] { blend_sr_models(m, other, 0.5, "blend"); }), "different residual smoothing");
  EXPECT_EQ(blend_sr_models(m, m, 0.5, "blend").residual_smoothing.iterations, 2);
}

// LibTorch, the C++ reference and the OpenCL kernels give the same smoothed
// output, the network's output passed through the filter; with correctives
// too, the filter comes first.
TEST_F(ResidualSmoothingModels, EveryInferencePathSmoothesTheSameWay) {
  auto m = fixtures::random_model(true, true, 21, true, true);
  m->residual_smoothing = {0.5, 2};
  auto plain = std::make_shared<SrModel>(*m);
  plain->residual_smoothing = {};
  const int N = m->num_lr, M = m->num_hr;
  auto cpu = make_cpu_inference(m), cpu_plain = make_cpu_inference(plain), cl = make_cl_inference(m);
  TorchPredictor torch_pred(*m);
  ResidualSmoother smoother(m->residual_smoothing, m->geometry);
  const auto frames = fixtures::lr_frames(*m, 2);
  for (int f = 0; f < 2; ++f) {
    const auto xf = frames[f].contiguous();
    const std::vector<float> x(xf.data_ptr<float>(), xf.data_ptr<float>() + 3 * N);
    std::vector<float> y_cpu(3 * size_t(M)), y_plain(3 * size_t(M)), y_cl(3 * size_t(M));
    cpu->infer(x.data(), y_cpu.data());
    cpu_plain->infer(x.data(), y_plain.data());
    cl->infer(x.data(), y_cl.data());
    const auto ref = torch_pred.predict(xf.unsqueeze(0).clone());
    const std::vector<float> y_torch(ref.data_ptr<float>(), ref.data_ptr<float>() + 3 * size_t(M));
    EXPECT_LT(max_abs_diff(y_cpu, y_torch), 1e-4) << f;
    EXPECT_LT(max_abs_diff(y_cl, y_torch), 1e-4) << f;
    std::vector<float> expected = y_plain;
    smoother.apply(x.data(), expected.data());
    EXPECT_LT(max_abs_diff(y_cpu, expected), 1e-6) << f;
    EXPECT_GT(max_abs_diff(y_cpu, y_plain), 1e-4) << f << ": the smoothing should be visible";
  }
  // Profiled runs time it as a stage of its own, before the correctives.
  m->rest_correctives.shapes = {"a"};
  m->rest_correctives.amplitudes = {{0.05f}};
  m->rest_correctives.lr = random_values(3 * size_t(N), 4, 1.0f);
  m->rest_correctives.hr = random_values(3 * size_t(M), 5, 0.5f);
  ClInferenceOptions o;
  o.profile = true;
  auto profiled = make_cl_inference(m, o);
  std::vector<float> x(3 * size_t(N), 0.0f), y(3 * size_t(M));
  profiled->infer(x.data(), y.data());
  const auto p = profiled->last_profile();
  ASSERT_GE(p.size(), 2u);
  EXPECT_EQ(p[p.size() - 2].first, "residual smoothing");
  EXPECT_EQ(p.back().first, "rest correctives");
}

TEST_F(ResidualSmoothingModels, ModelSmoothCliWritesItAndRefusesBadInput) {
  const auto m = fixtures::random_model(true, true, 31, true, true);
  save_sr_model(path("m.fsm"), *m);
  auto r = run("model smooth " + q("m.fsm") + " --lambda 0.25 --iterations 3 -o " + q("s.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["residual_smoothing"]["lambda"], 0.25);
  EXPECT_EQ(j["residual_smoothing"]["iterations"], 3);
  EXPECT_EQ(load_sr_model(path("s.fsm")).residual_smoothing.iterations, 3);
  // --iterations 0 removes it.
  r = run("model smooth " + q("s.fsm") + " --iterations 0 -o " + q("s0.fsm") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["residual_smoothing"].is_null());
  EXPECT_TRUE(load_sr_model(path("s0.fsm")).residual_smoothing.empty());

  r = run("model smooth " + q("m.fsm") + " --lambda 1.5 --iterations 2 -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "lambda must be in (0, 1]");
  EXPECT_FALSE(fs::exists(path("x.fsm")));

  auto with = *m;
  with.rest_correctives.shapes = {"a"};
  with.rest_correctives.amplitudes = {{0.05f}};
  with.rest_correctives.lr = random_values(3 * size_t(m->num_lr), 4, 1.0f);
  with.rest_correctives.hr = random_values(3 * size_t(m->num_hr), 5, 0.5f);
  save_sr_model(path("c.fsm"), with);
  r = run("model smooth " + q("c.fsm") + " --iterations 2 -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "fit them again");
  EXPECT_FALSE(fs::exists(path("x.fsm")));

  auto no_skip = *fixtures::random_model(true, true, 31, false, true);
  save_sr_model(path("n.fsm"), no_skip);
  r = run("model smooth " + q("n.fsm") + " --iterations 2 -o " + q("x.fsm"));
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "with the embedded skip");
  EXPECT_FALSE(fs::exists(path("x.fsm")));
}

}  // namespace
}  // namespace facesr
