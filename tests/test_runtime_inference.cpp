// Runtime inference without LibTorch: the C++ reference and the OpenCL
// kernels against the LibTorch network on the same frames, and the
// load-time upsampling weights against the network's.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "compute/cl_buffer.h"
#include "core/error.h"
#include "compute/cl_context.h"
#include "compute/cl_program.h"
#include "rig/rig_io.h"
#include "runtime/sr_inference.h"
#include "sr/sr_geometry.h"
#include "sr/sr_model.h"
#include "sr_fixtures.h"
#include "test_support.h"
#include "train/model_export.h"
#include "train/sr_network.h"
#include "train/torch_predictor.h"

namespace facesr {
namespace {

using fixtures::lr_frames;
using fixtures::random_model;

TEST(RuntimeInference, CpuReferenceMatchesLibTorch) {
  for (int variant = 0; variant < 5; ++variant) {
    const bool fe = variant != 1, cu = variant != 2, skip = variant >= 3, zero_rest = variant == 4;
    const auto m = random_model(fe, cu, 3 + variant, skip, zero_rest);
    const auto lr = lr_frames(*m, 3);
    const auto ref = TorchPredictor(*m).predict(lr);
    auto cpu = make_cpu_inference(m);
    double worst = 0;
    for (int f = 0; f < 3; ++f) {
      std::vector<float> out(size_t(3 * m->num_hr));
      const auto in = lr[f].contiguous();
      cpu->infer(in.data_ptr<float>(), out.data());
      const auto got = torch::from_blob(out.data(), {m->num_hr, 3});
      worst = std::max(worst, (got - ref[f]).norm(2, 1).max().item<double>());
    }
    EXPECT_LT(worst, 1e-4) << "max per-vertex difference (cm), variant " << variant;
    EXPECT_GT(ref.abs().max().item<double>(), 1e-3) << "the network output should not be trivially zero";
  }
}

// Max per-vertex distance (cm) between an inference's output and LibTorch's.
double worst_difference(SrInference& inf, const torch::Tensor& lr, const torch::Tensor& ref, int M) {
  double worst = 0;
  for (int64_t f = 0; f < lr.size(0); ++f) {
    std::vector<float> out(size_t(3 * M));
    const auto in = lr[f].contiguous();
    inf.infer(in.data_ptr<float>(), out.data());
    worst = std::max(worst, (torch::from_blob(out.data(), {M, 3}) - ref[f]).norm(2, 1).max().item<double>());
  }
  return worst;
}

TEST(RuntimeInference, OpenClMatchesLibTorch) {
  for (int variant = 0; variant < 5; ++variant) {
    const bool fe = variant != 1, cu = variant != 2, skip = variant >= 3, zero_rest = variant == 4;
    const auto m = random_model(fe, cu, 11 + variant, skip, zero_rest);
    const auto lr = lr_frames(*m, 3);
    const auto ref = TorchPredictor(*m).predict(lr);
    // The CPU device's 16-wide kernels, and the GPU path (tiled dense layers,
    // one k-NN query per work-item) run on the same device.
    for (ClKernels kernels : {ClKernels::Auto, ClKernels::Tiled}) {
      ClInferenceOptions o;
      o.kernels = kernels;
      o.knn = kernels == ClKernels::Tiled ? ClKnn::Full : ClKnn::Auto;
      auto cl = make_cl_inference(m, o);
      EXPECT_LT(worst_difference(*cl, lr, ref, m->num_hr), 1e-4)
          << "variant " << variant << (kernels == ClKernels::Tiled ? ", tiled kernels" : "");
    }
  }
}

// The shipped ICT model (samples/assets/ict.fsm, full size: 2,885 LR nodes,
// 9,409 HR vertices) through the CPU device's default kernels against
// LibTorch, on smooth LR displacements of a few millimetres.
TEST(RuntimeInference, ShippedIctModelOpenClMatchesLibTorch) {
  const std::string path = std::string(FACESR_TEST_SOURCE_DIR) + "/samples/assets/ict.fsm";
  const auto m = std::make_shared<SrModel>(load_sr_model(path));
  torch::manual_seed(3);
  const auto lr = lr_frames(*m, 2);
  const auto ref = TorchPredictor(*m).predict(lr);
  auto cl = make_cl_inference(m);
  const double worst = worst_difference(*cl, lr, ref, m->num_hr);
  std::printf("ICT model: max per-vertex difference %.3g cm\n", worst);
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(ref.abs().max().item<double>(), 1e-2);
}

// With zero_rest the rest input gives exactly the rest surface in LibTorch,
// the C++ reference and the OpenCL kernels; the same weights without it do not.
TEST(RuntimeInference, ZeroRestMapsTheRestInputToTheRestSurface) {
  for (bool zero_rest : {false, true}) {
    const auto m = random_model(true, true, 21, true, zero_rest);
    const auto rest = torch::zeros({1, m->num_lr, 3});
    const double torch_max = TorchPredictor(*m).predict(rest).abs().max().item<double>();
    std::vector<float> zero(size_t(3 * m->num_lr), 0.0f), out(size_t(3 * m->num_hr));
    double cpu_max = 0, cl_max = 0;
    make_cpu_inference(m)->infer(zero.data(), out.data());
    for (float v : out) cpu_max = std::max(cpu_max, double(std::abs(v)));
    make_cl_inference(m)->infer(zero.data(), out.data());
    for (float v : out) cl_max = std::max(cl_max, double(std::abs(v)));
    if (zero_rest) {
      EXPECT_LT(torch_max, 1e-6);
      EXPECT_LT(cpu_max, 1e-6);
      EXPECT_LT(cl_max, 1e-6);
    } else {
      EXPECT_GT(torch_max, 1e-3) << "a random network is not zero at rest by itself";
      EXPECT_GT(cl_max, 1e-3);
    }
  }
}

TEST(RuntimeInference, EveryFeatureKnnVariantGivesTheSameOutputAsTheFullScan) {
  // Identical neighbours give bit-identical outputs; any missed neighbour
  // changes the EdgeConv maximum somewhere.
  const auto m = random_model(true, true, 17);
  auto with = [&](ClKnn knn) {
    ClInferenceOptions o;
    o.knn = knn;
    return make_cl_inference(m, o);
  };
  auto full = with(ClKnn::Full), simd = with(ClKnn::Simd), pruned = with(ClKnn::Pruned),
       symmetric = with(ClKnn::Symmetric);
  // A list of k entries overflows for most nodes: the full-scan redo path.
  ClInferenceOptions tight;
  tight.knn = ClKnn::Symmetric;
  tight.knn_list = m->arch.graph_k;
  auto redo = make_cl_inference(m, tight);
  // Symmetric bounds each frame by the last one's neighbours: frames in
  // order, then out of order and repeated (bounds from an unrelated frame).
  const auto lr = lr_frames(*m, 4);
  for (int64_t f : {0, 1, 2, 3, 3, 0, 2}) {
    std::vector<float> of(size_t(3 * m->num_hr)), os(of.size()), op(of.size()), oy(of.size()), orr(of.size());
    const auto in = lr[f].contiguous();
    full->infer(in.data_ptr<float>(), of.data());
    simd->infer(in.data_ptr<float>(), os.data());
    pruned->infer(in.data_ptr<float>(), op.data());
    symmetric->infer(in.data_ptr<float>(), oy.data());
    redo->infer(in.data_ptr<float>(), orr.data());
    EXPECT_EQ(of, os) << "frame " << f;
    EXPECT_EQ(of, op) << "frame " << f;
    EXPECT_EQ(of, oy) << "frame " << f;
    EXPECT_EQ(of, orr) << "frame " << f;
  }
  ClInferenceOptions bad;
  bad.knn_list = 0;
  EXPECT_THROW(make_cl_inference(m, bad), Error);
}

// The CPU dense kernels with 16 and 32 outputs per work-item sum each
// output in the same order: bit-identical outputs. A reconstruction layer
// of 50 outputs (padded to 64) exercises the 32-wide kernel's partial half.
TEST(RuntimeInference, DenseKernelWidthsGiveIdenticalOutputs) {
  const auto m = random_model(true, true, 23, false, false, {50, 64});
  const auto lr = lr_frames(*m, 2);
  const auto ref = TorchPredictor(*m).predict(lr);
  auto with = [&](int width) {
    ClInferenceOptions o;
    o.kernels = ClKernels::Simd;
    o.dense_width = width;
    return make_cl_inference(m, o);
  };
  auto w16 = with(16), w32 = with(32), automatic = with(0);
  for (int64_t f = 0; f < lr.size(0); ++f) {
    std::vector<float> a(size_t(3 * m->num_hr)), b(a.size()), c(a.size());
    const auto in = lr[f].contiguous();
    w16->infer(in.data_ptr<float>(), a.data());
    w32->infer(in.data_ptr<float>(), b.data());
    automatic->infer(in.data_ptr<float>(), c.data());
    EXPECT_EQ(a, b) << "frame " << f;
    EXPECT_EQ(a, c) << "frame " << f;
  }
  EXPECT_LT(worst_difference(*w32, lr, ref, m->num_hr), 1e-4);
  ClInferenceOptions bad;
  bad.dense_width = 24;
  EXPECT_THROW(make_cl_inference(m, bad), Error);
}

TEST(RuntimeInference, OpenClProfileNamesEveryStage) {
  const auto m = random_model(true, true, 2);
  ClInferenceOptions o;
  o.profile = true;
  auto cl = make_cl_inference(m, o);
  std::vector<float> in(size_t(3 * m->num_lr), 0.01f), out(size_t(3 * m->num_hr));
  cl->infer(in.data(), out.data());
  const auto p = cl->last_profile();
  ASSERT_GE(p.size(), 6u);
  for (const auto& [name, ms] : p) EXPECT_GE(ms, 0) << name;
}

}  // namespace

// The CPU kernels' SIREN sine (sin16 in cl/sr_infer.cl) against double sin:
// random arguments over the range SIREN layers produce and beyond, plus
// multiples of π/2 and the half-way points where the reduction switches k.
TEST(RuntimeInference, FastSineMatchesSin) {
  compute::Context ctx;
  const compute::Program prog = ctx.build_program({"sr_infer.cl"}, "-cl-std=CL1.2");
  std::vector<float> x;
  std::mt19937 rng(5);
  for (const double range : {2.0, 50.0, 1e4}) {
    std::uniform_real_distribution<double> u(-range, range);
    for (int i = 0; i < 20000; ++i) x.push_back(float(u(rng)));
  }
  for (int k = -200; k <= 200; ++k)
    for (const double f : {0.0, 0.5, 0.25}) x.push_back(float((k + f) * M_PI));
  x.push_back(0.0f);
  x.push_back(-0.0f);
  x.push_back(1e-30f);
  while (x.size() % 16) x.push_back(1.0f);
  compute::Buffer<float> in(ctx, x), out(ctx, x.size());
  compute::Kernel kern = prog.kernel("sin16_values");
  kern.args(in, out).run_1d(x.size() / 16);
  const std::vector<float> y = out.download();
  double worst = 0;
  for (size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(double(y[i]) - std::sin(double(x[i]))));
  std::printf("max |sin16 - sin| = %.3g over %zu arguments\n", worst, x.size());
  EXPECT_LT(worst, 2e-7);
}

}  // namespace facesr
