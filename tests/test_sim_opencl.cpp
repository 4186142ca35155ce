// OpenCL simulator against the CPU reference on the procedural head: forces
// to 1e-5 relative, converged positions to 1e-4 of the face size, plus
// robustness over 1,000 random control frames.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "core/error.h"
#include "sim/cl_simulator.h"
#include "sim/cpu_forces.h"
#include "test_support.h"

using namespace facesr;

namespace {

Controls zero_controls(const SimModel& m) {
  Controls c;
  c.weights.assign(m.num_shapes, 0.0f);
  return c;
}

// Index of a blendshape; throws so that a renamed shape fails loudly.
int shape_index(const SimModel& m, const std::string& name) {
  for (int b = 0; b < m.num_shapes; ++b)
    if (m.shape_names[b] == name || m.shape_names[b] == name + "_L") return b;
  throw Error("test rig has no blendshape " + name);
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// Each parity test runs with both element-kernel variants, eight tets per
// work-item (the CPU default) and one tet per work-item (the GPU default),
// with the assembled CG product (the default), and the eight-tet kernels
// once more with the per-element product.
struct Variant {
  ClSimulatorOptions::Elements elements;
  ClSimulatorOptions::Product product;
};

class SimOpenCLElements : public ::testing::TestWithParam<Variant> {
 protected:
  ClSimulatorOptions options() const {
    ClSimulatorOptions o;
    o.elements = GetParam().elements;
    o.product = GetParam().product;
    return o;
  }
};

}  // namespace

INSTANTIATE_TEST_SUITE_P(Kernels, SimOpenCLElements,
                         ::testing::Values(Variant{ClSimulatorOptions::Elements::Simd, ClSimulatorOptions::Product::Assembled},
                                           Variant{ClSimulatorOptions::Elements::Scalar, ClSimulatorOptions::Product::Assembled},
                                           Variant{ClSimulatorOptions::Elements::Simd, ClSimulatorOptions::Product::Elements}),
                         [](const auto& info) {
                           const bool simd = info.param.elements == ClSimulatorOptions::Elements::Simd;
                           const bool assembled = info.param.product == ClSimulatorOptions::Product::Assembled;
                           return std::string(simd ? "Simd" : "Scalar") + (assembled ? "Assembled" : "ElementProduct");
                         });

// With a point spring the CG product runs per surface vertex; without one
// the track springs' share is the fixed node matrix (the L matrix of gather_dot in cl/sim.cl).
TEST_P(SimOpenCLElements, ConvergedPositionsMatchCpuReference) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  SolverOptions opt;
  opt.newton_tol = 1e-6;
  opt.newton_max = 40;
  opt.cg_tol = 1e-6;
  opt.cg_max = 2000;
  for (const bool spring : {true, false}) {
    SCOPED_TRACE(spring ? "with a point spring" : "track springs only");
    auto cpu = make_cpu_simulator(m, opt);
    auto gpu = make_cl_simulator(m, opt, options());
    std::printf("device: %s\n", gpu->device().c_str());
    Controls c = zero_controls(m);
    c.weights[shape_index(m, "jawOpen")] = 0.6f;
    c.weights[shape_index(m, "mouthSmile_L")] = 1.0f;
    c.weights[shape_index(m, "browInnerUp")] = 0.5f;
    if (spring) c.springs.push_back({m.num_surface / 3, Vec3(0, -4, 12), 1.0});
    const StepStats a = cpu->step(c);
    const StepStats b = gpu->step(c);
    std::printf("cpu: newton %d cg %d rel %.2e %.1f ms | cl: newton %d cg %d rel %.2e %.1f ms\n", a.newton_iters,
                a.cg_iters, a.rel_residual, a.ms, b.newton_iters, b.cg_iters, b.rel_residual, b.ms);
    EXPECT_TRUE(a.converged);
    EXPECT_TRUE(b.converged);
    EXPECT_GT(a.newton_iters, 0);
    std::vector<double> xa, xb, sa, sb;
    cpu->nodes(xa);
    gpu->nodes(xb);
    EXPECT_LT(max_abs_diff(xa, xb), 1e-4 * m.face_size);
    EXPECT_GT(max_abs_diff(xa, m.rest), 0.05);  // it did move
    cpu->surface(sa);
    gpu->surface(sb);
    EXPECT_LT(max_abs_diff(sa, sb), 1e-4 * m.face_size);
    EXPECT_NEAR(a.energy, b.energy, 1e-6 * std::abs(a.energy));
    EXPECT_EQ(a.inverted_tets, b.inverted_tets);
  }
}

TEST_P(SimOpenCLElements, ForcesMatchCpuReference) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  auto cpu = make_cpu_simulator(m);
  auto gpu = make_cl_simulator(m, {}, options());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  std::vector<double> x = m.rest;
  for (double& v : x) v += u(rng);
  cpu->set_nodes(x);
  gpu->set_nodes(x);
  Controls c = zero_controls(m);
  for (auto& w : c.weights) w = float(std::uniform_real_distribution<double>(0, 1)(rng));
  c.springs.push_back({m.num_surface / 2, Vec3(1, -3, 12), 3.0});
  std::vector<double> s;
  cpu->surface(s);
  c.spheres.push_back({Vec3(s[60], s[61], s[62] + 0.2), 1.5, 4.0});
  std::vector<double> fa, fb;
  cpu->forces(c, fa);
  gpu->forces(c, fb);
  double num = 0, den = 0;
  for (size_t i = 0; i < fa.size(); ++i) num += (fa[i] - fb[i]) * (fa[i] - fb[i]), den += fa[i] * fa[i];
  std::printf("relative force difference %.2e (|f| = %.3g)\n", std::sqrt(num / den), std::sqrt(den));
  EXPECT_GT(den, 0.0);
  EXPECT_LT(std::sqrt(num / den), 1e-5);
}

TEST_P(SimOpenCLElements, SinglePrecisionStaysCloseToReference) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  ClSimulatorOptions single = options();
  single.single_precision = true;
  SolverOptions opt;
  opt.newton_tol = 1e-4;
  opt.cg_tol = 1e-4;
  auto cpu = make_cpu_simulator(m, opt);
  auto gpu = make_cl_simulator(m, opt, single);
  EXPECT_NE(gpu->device().find("float"), std::string::npos);
  Controls c = zero_controls(m);
  c.weights[shape_index(m, "jawOpen")] = 0.5f;
  c.weights[shape_index(m, "mouthSmile_R")] = 0.8f;
  cpu->step(c);
  const StepStats st = gpu->step(c);
  EXPECT_LT(st.rel_residual, 1e-3);
  std::vector<double> xa, xb;
  cpu->nodes(xa);
  gpu->nodes(xb);
  EXPECT_LT(max_abs_diff(xa, xb), 1e-3 * m.face_size);
}

TEST(SimOpenCL, ThousandRandomFramesStayFinite) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  SolverOptions opt;  // the real-time settings a game would use
  opt.newton_max = 3;
  opt.cg_max = 60;
  opt.cg_tol = 0.05;
  auto sim = make_cl_simulator(m, opt);
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0, 1);
  int rejected = 0, nan_frames = 0, max_inverted = 0;
  std::vector<double> x;
  for (int f = 0; f < 1000; ++f) {
    Controls c = zero_controls(m);
    const double kind = u(rng);
    for (auto& w : c.weights) {
      const double r = u(rng);
      w = kind < 0.3 ? float(r < 0.5 ? 0.0 : 1.0)   // extremes
                     : float(r * r);                // typical: mostly small
    }
    if (f % 10 == 7) {  // invalid frames must be rejected without touching the state
      const int b = int(u(rng) * m.num_shapes) % m.num_shapes;
      c.weights[b] = (f % 20 == 7) ? std::numeric_limits<float>::quiet_NaN() : 1.5f;
      EXPECT_THROW(sim->step(c), Error);
      ++rejected;
      continue;
    }
    const StepStats st = sim->step(c);
    max_inverted = std::max(max_inverted, st.inverted_tets);
    sim->nodes(x);
    bool finite = std::isfinite(st.rel_residual) && std::isfinite(st.energy);
    for (double v : x) finite = finite && std::isfinite(v);
    nan_frames += !finite;
  }
  std::printf("rejected %d, NaN frames %d, max inverted tets %d\n", rejected, nan_frames, max_inverted);
  EXPECT_EQ(rejected, 100);
  EXPECT_EQ(nan_frames, 0);
}

// The CG's scalars live on the device and the host reads its stopping flags
// once per batch: the iterates must not depend on the batch size (1 checks
// after every iteration), with and without point springs and spheres (the
// per-vertex surface product), and a negative batch is refused.
TEST(SimOpenCL, CgBatchSizeDoesNotChangeTheSolve) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  SolverOptions opt = realtime_solver();
  std::vector<Controls> frames;
  for (int f = 0; f < 6; ++f) {
    Controls c = zero_controls(m);
    c.weights[shape_index(m, "jawOpen")] = 0.15f * float(f);
    c.weights[shape_index(m, "mouthSmile_R")] = 0.1f * float(6 - f);
    if (f >= 3) c.springs.push_back({m.num_surface / 3, Vec3(0.5, -1, 0.5 * f), 5.0});
    if (f == 5) c.spheres.push_back({Vec3(0, -2, 9), 1.0, 50.0});
    frames.push_back(c);
  }
  auto run = [&](int batch) {
    ClSimulatorOptions cl;
    cl.cg_batch = batch;
    auto sim = make_cl_simulator(m, opt, cl);
    std::vector<std::vector<double>> nodes;
    std::vector<int> cg;
    for (const Controls& c : frames) {
      cg.push_back(sim->step(c).cg_iters);
      nodes.emplace_back();
      sim->nodes(nodes.back());
    }
    return std::make_pair(nodes, cg);
  };
  const auto [ref_nodes, ref_cg] = run(1);
  int total = 0;
  for (int n : ref_cg) total += n;
  EXPECT_GT(total, 6);  // the frames need real solves
  for (int batch : {0, 3, 64}) {
    const auto [nodes, cg] = run(batch);
    EXPECT_EQ(cg, ref_cg) << "batch " << batch;
    for (size_t f = 0; f < frames.size(); ++f) EXPECT_EQ(nodes[f], ref_nodes[f]) << "batch " << batch << " frame " << f;
  }
  ClSimulatorOptions bad;
  bad.cg_batch = -1;
  EXPECT_THROW(make_cl_simulator(m, opt, bad), Error);
}
