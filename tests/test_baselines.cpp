// RBF and MLS baselines (paper appendix A.2, A.3) on the procedural rig's SR
// geometry: interpolation and reproduction properties, input checks, and
// the σ fit.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <random>

#include "baselines/fit_sigma.h"
#include "baselines/mls.h"
#include "baselines/rbf.h"
#include "sr/sr_geometry.h"
#include "test_support.h"

using namespace facesr;

namespace {

using fixtures::error_of;
using fixtures::procedural_rig;

const SrGeometry& geometry() {
  static const SrGeometry g = build_sr_geometry(procedural_rig());
  return g;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A smooth displacement field of the LR rest positions (cm), with `phase`
// making different frames.
std::vector<float> smooth_field(const SrGeometry& g, double phase) {
  std::vector<float> d(size_t(g.num_lr) * 3);
  for (int i = 0; i < g.num_lr; ++i) {
    const float* x = &g.lr_rest[size_t(i) * 3];
    d[size_t(i) * 3 + 0] = float(0.3 * std::sin(0.4 * x[1] + phase));
    d[size_t(i) * 3 + 1] = float(0.2 * std::cos(0.3 * x[0] - 0.2 * x[2] + 2 * phase));
    d[size_t(i) * 3 + 2] = float(0.1 * std::sin(0.25 * (x[0] + x[1]) + 3 * phase));
  }
  return d;
}

double max_abs(const std::vector<float>& v) {
  double m = 0;
  for (float x : v) m = std::max(m, double(std::abs(x)));
  return m;
}

// One HR vertex over four LR nodes whose x take two values, y one and z four.
SrGeometry degenerate_geometry() {
  SrGeometry g;
  g.num_lr = 4;
  g.num_hr = 1;
  g.graph_k = 1;
  g.upsample_k = 4;
  g.lr_rest = {0, 5, 0, 0, 5, 1, 1, 5, 2, 1, 5, 3};
  g.hr_rest = {0.5f, 5, 1.5f};
  g.hr_rest_lr_frame = g.hr_rest;
  g.lr_graph = {1, 0, 3, 2};
  g.lr_to_hr = {0, -1, -1, -1};
  g.up_index = {0, 1, 2, 3};
  g.up_dist = {0.5f, 1, 1.5f, 2};
  g.euclid_index = g.up_index;
  g.euclid_dist = g.up_dist;
  return g;
}

}  // namespace

// ----------------------------------------------------------------------- RBF

namespace {

// Largest |HR − LR| over the mapped vertices' components.
double node_misfit(const SrGeometry& g, const std::vector<float>& lr, const std::vector<float>& hr) {
  double worst = 0;
  for (int i = 0; i < g.num_lr; ++i) {
    const int j = g.lr_to_hr[size_t(i)];
    if (j < 0) continue;
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, double(std::abs(hr[size_t(j) * 3 + size_t(c)] - lr[size_t(i) * 3 + size_t(c)])));
  }
  return worst;
}

// Mean |HR − f(HR vertex)| for the smooth field f of smooth_field (phase 0.3).
double smooth_field_error(const SrGeometry& g, const std::vector<float>& hr) {
  SrGeometry at_hr = g;  // evaluate the same field at the HR vertices (LR frame)
  at_hr.num_lr = g.num_hr;
  at_hr.lr_rest = g.hr_rest_lr_frame;
  const std::vector<float> want = smooth_field(at_hr, 0.3);
  double sum = 0;
  for (int j = 0; j < g.num_hr; ++j)
    sum += std::hypot(hr[size_t(j) * 3] - want[size_t(j) * 3], hr[size_t(j) * 3 + 1] - want[size_t(j) * 3 + 1],
                      hr[size_t(j) * 3 + 2] - want[size_t(j) * 3 + 2]);
  return sum / g.num_hr;
}

}  // namespace

TEST(RbfBaseline, InterpolatesTheLrDataAtMappedVerticesWithoutRegularisation) {
  // μ = 0 is the paper's Φ W = D: any data, smooth or not, is matched where
  // the LR nodes map.
  const SrGeometry& g = geometry();
  std::mt19937 rng(2);
  std::normal_distribution<float> n01;
  std::vector<float> lr = smooth_field(g, 0.3);
  for (float& v : lr) v += 0.05f * n01(rng);
  for (double sigma : {1.0, 2.5}) {
    const RbfBaseline rbf(g, sigma, 0.0);
    EXPECT_EQ(rbf.regularization(), 0.0);
    EXPECT_LT(node_misfit(g, lr, rbf.apply(lr)), 1e-3 * max_abs(lr)) << "sigma " << sigma;
  }
}

TEST(RbfBaseline, RegularisationTradesNodeFitForSmoothness) {
  const SrGeometry& g = geometry();
  const std::vector<float> lr = smooth_field(g, 0.3);
  double last_misfit = -1;
  for (double mu : {0.0, 1e-3, 1e-2, 1e-1}) {
    const auto t0 = std::chrono::steady_clock::now();
    const RbfBaseline rbf(g, 2.0, mu);
    const double build_s = seconds_since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    const std::vector<float> hr = rbf.apply(lr);
    const double apply_s = seconds_since(t1);
    const double misfit = node_misfit(g, lr, hr);
    std::cout << "[ timing ] RBF sigma 2 mu " << mu << ": build " << build_s << " s, apply " << apply_s
              << " s, rcond " << rbf.rcond() << ", stored " << rbf.stored_fraction() << " of M x N, node misfit "
              << misfit << " cm, smooth-field error " << smooth_field_error(g, hr) << " cm\n";
    EXPECT_GT(rbf.rcond(), 0);
    EXPECT_LE(rbf.stored_fraction(), 1.0);
    EXPECT_GE(misfit, last_misfit - 1e-6) << "mu " << mu;
    last_misfit = misfit;
  }
}

TEST(RbfBaseline, ReproducesARigidTranslation) {
  // Gaussian RBFs have no constant term, so a translation is matched at the
  // nodes and approximated in between: closely once σ spans a few node
  // spacings (μ = 0).
  const SrGeometry& g = geometry();
  std::vector<float> lr(size_t(g.num_lr) * 3);
  for (int i = 0; i < g.num_lr; ++i) {
    lr[size_t(i) * 3 + 0] = 1.0f;
    lr[size_t(i) * 3 + 1] = -2.0f;
    lr[size_t(i) * 3 + 2] = 0.5f;
  }
  for (double mu : {0.0, RbfBaseline::kRegularization}) {
    const RbfBaseline rbf(g, 2.5 * procedural_rig().lattice.cell, mu);
    const std::vector<float> hr = rbf.apply(lr);
    double worst = 0, mean = 0;
    for (int j = 0; j < g.num_hr; ++j) {
      const double e = std::hypot(hr[size_t(j) * 3] - 1.0, hr[size_t(j) * 3 + 1] + 2.0, hr[size_t(j) * 3 + 2] - 0.5);
      worst = std::max(worst, e);
      mean += e / g.num_hr;
    }
    std::cout << "[ info ] RBF mu " << mu << ", translation of 2.29 cm: mean error " << mean << " cm, max " << worst
              << " cm\n";
    // Regularisation shrinks the weights, and with them the field between
    // and at the nodes: measured mean 0.6 %, max 6 % at the default μ.
    EXPECT_LT(mean, (mu > 0 ? 0.02 : 0.001) * 2.29);
    EXPECT_LT(worst, (mu > 0 ? 0.1 : 0.001) * 2.29);
  }
}

TEST(RbfBaseline, RejectsBadInput) {
  const SrGeometry& g = geometry();
  EXPECT_NE(error_of([&] { RbfBaseline(g, 0.0); }).find("sigma"), std::string::npos);
  EXPECT_NE(error_of([&] { RbfBaseline(g, std::nan("")); }).find("sigma"), std::string::npos);
  EXPECT_NE(error_of([&] { RbfBaseline(g, 1.0, -1e-3); }).find("regularization"), std::string::npos);
  SrGeometry no_tris = g;
  no_tris.hr_tris.clear();
  EXPECT_NE(error_of([&] { RbfBaseline(no_tris, 1.0); }).find("hr_tris"), std::string::npos);
  SrGeometry bad = g;
  bad.lr_to_hr.pop_back();
  EXPECT_NE(error_of([&] { RbfBaseline(bad, 1.0); }).find("RBF baseline: lr_to_hr has"), std::string::npos);
  const RbfBaseline rbf(g, 1.5);
  std::vector<float> lr(size_t(g.num_lr) * 3, 0.f);
  EXPECT_NE(error_of([&] { rbf.apply(std::vector<float>(lr.begin(), lr.end() - 1)); }).find("expected"),
            std::string::npos);
  lr[7] = std::nanf("");
  EXPECT_NE(error_of([&] { rbf.apply(lr); }).find("node 2 is not finite"), std::string::npos);
}

// ----------------------------------------------------------------------- MLS

TEST(MlsBaseline, ReproducesPolynomialsOfEachComponent) {
  const SrGeometry& g = geometry();
  const auto t0 = std::chrono::steady_clock::now();
  const MlsBaseline mls(g, 2.0);
  std::cout << "[ timing ] MLS build " << seconds_since(t0) << " s\n";
  long count[3] = {0, 0, 0};
  for (uint8_t d : mls.degree()) ++count[d];
  std::cout << "[ info ] MLS fit degrees 0/1/2: " << count[0] << " / " << count[1] << " / " << count[2] << "\n";
  EXPECT_GT(count[2], 0);
  // f_c(x) = a_c + b_c x_c + q_c x_c² with x centred near the face, for each degree.
  const double a[3] = {0.4, -0.3, 0.2}, b[3] = {0.05, 0.08, -0.06}, q[3] = {0.01, -0.02, 0.015};
  for (int deg = 0; deg <= 2; ++deg) {
    std::vector<float> lr(size_t(g.num_lr) * 3);
    const auto f = [&](int c, double x) { return a[c] + (deg >= 1 ? b[c] * x : 0) + (deg >= 2 ? q[c] * x * x : 0); };
    for (int i = 0; i < g.num_lr; ++i)
      for (int c = 0; c < 3; ++c) lr[size_t(i) * 3 + size_t(c)] = float(f(c, g.lr_rest[size_t(i) * 3 + size_t(c)]));
    const auto t1 = std::chrono::steady_clock::now();
    const std::vector<float> hr = mls.apply(lr);
    if (deg == 0) std::cout << "[ timing ] MLS apply " << seconds_since(t1) << " s\n";
    long checked = 0;
    for (int j = 0; j < g.num_hr; ++j)
      for (int c = 0; c < 3; ++c) {
        if (mls.degree()[size_t(j) * 3 + size_t(c)] < deg) continue;
        const double want = f(c, g.hr_rest_lr_frame[size_t(j) * 3 + size_t(c)]);
        ASSERT_NEAR(hr[size_t(j) * 3 + size_t(c)], want, 1e-4 * (1 + std::abs(want)))
            << "degree " << deg << " vertex " << j << " component " << c;
        ++checked;
      }
    EXPECT_GT(checked, 0);
  }
}

TEST(MlsBaseline, IsAWeightedAverageOfTheNeighbours) {
  const SrGeometry& g = geometry();
  const MlsBaseline mls(g, 1.5);
  const int k = g.upsample_k;
  ASSERT_EQ(mls.weights().size(), size_t(g.num_hr) * 3 * k);
  const std::vector<float> lr = smooth_field(g, 1.1);
  const std::vector<float> hr = mls.apply(lr);
  for (int j = 0; j < g.num_hr; ++j)
    for (int c = 0; c < 3; ++c) {
      const float* w = &mls.weights()[(size_t(j) * 3 + size_t(c)) * k];
      double sum = 0, v = 0;
      for (int s = 0; s < k; ++s) {
        sum += w[s];
        v += double(w[s]) * lr[size_t(g.up_index[size_t(j) * k + size_t(s)]) * 3 + size_t(c)];
      }
      ASSERT_NEAR(sum, 1.0, 1e-5) << "vertex " << j;
      ASSERT_NEAR(hr[size_t(j) * 3 + size_t(c)], v, 1e-5);
    }
}

TEST(MlsBaseline, DropsDegreeOnDegenerateNeighbourhoods) {
  const SrGeometry g = degenerate_geometry();
  const MlsBaseline mls(g, 1.0);
  ASSERT_EQ(mls.degree().size(), 3u);
  EXPECT_EQ(mls.degree()[0], 1);  // x: two distinct values
  EXPECT_EQ(mls.degree()[1], 0);  // y: one value
  EXPECT_EQ(mls.degree()[2], 2);  // z: four values
  // Each fit is still exact for what its degree can represent:
  // Δx = 0.5 + 0.1 x, Δy = 7, Δz = 0.2 + 0.2 z + 0.1 z².
  std::vector<float> lr(12);
  for (int i = 0; i < 4; ++i) {
    const float x = g.lr_rest[size_t(i) * 3], z = g.lr_rest[size_t(i) * 3 + 2];
    lr[size_t(i) * 3 + 0] = 0.5f + 0.1f * x;
    lr[size_t(i) * 3 + 1] = 7.0f;
    lr[size_t(i) * 3 + 2] = 0.2f + 0.2f * z + 0.1f * z * z;
  }
  const std::vector<float> hr = mls.apply(lr);
  EXPECT_NEAR(hr[0], 0.5 + 0.1 * 0.5, 1e-5);
  EXPECT_NEAR(hr[1], 7.0, 1e-5);
  EXPECT_NEAR(hr[2], 0.2 + 0.2 * 1.5 + 0.1 * 1.5 * 1.5, 1e-5);
  // Far neighbours whose Gaussian weights underflow still give a fit.
  SrGeometry far = g;
  for (float& d : far.up_dist) d += 1000.f;
  const MlsBaseline mfar(far, 1.0);
  for (float v : mfar.apply(lr)) EXPECT_TRUE(std::isfinite(v));
}

TEST(MlsBaseline, RejectsBadInput) {
  const SrGeometry& g = geometry();
  EXPECT_NE(error_of([&] { MlsBaseline(g, -1.0); }).find("sigma"), std::string::npos);
  SrGeometry bad = g;
  bad.up_dist.resize(3);
  EXPECT_NE(error_of([&] { MlsBaseline(bad, 1.0); }).find("MLS baseline: up_dist has"), std::string::npos);
  bad = g;
  bad.up_dist[0] = -1.f;
  EXPECT_NE(error_of([&] { MlsBaseline(bad, 1.0); }).find("up_dist"), std::string::npos);
  const MlsBaseline mls(g, 1.0);
  std::vector<float> lr(size_t(g.num_lr) * 3, 0.f);
  EXPECT_NE(error_of([&] { mls.apply(std::vector<float>(3, 0.f)); }).find("expected"), std::string::npos);
  lr[0] = INFINITY;
  EXPECT_NE(error_of([&] { mls.apply(lr); }).find("node 0 is not finite"), std::string::npos);
  std::vector<float> out(size_t(g.num_hr) * 3);
  EXPECT_NE(error_of([&] { mls.apply(nullptr, out.data()); }).find("null"), std::string::npos);
}

// ------------------------------------------------------------------- σ fits

TEST(MlsBaseline, SigmaFitPicksTheGeneratingSigma) {
  const SrGeometry& g = geometry();
  // Ground truth made by MLS itself at σ = 1.5: that candidate has zero error.
  const MlsBaseline truth(g, 1.5);
  std::vector<std::vector<float>> lr, hr;
  for (int f = 0; f < 3; ++f) {
    lr.push_back(smooth_field(g, 0.7 * f));
    hr.push_back(truth.apply(lr.back()));
  }
  std::vector<const float*> lp, hp;
  for (int f = 0; f < 3; ++f) {
    lp.push_back(lr[size_t(f)].data());
    hp.push_back(hr[size_t(f)].data());
  }
  std::vector<double> err;
  EXPECT_EQ(fit_mls_sigma(g, lp, hp, {0.4, 1.5, 6.0}, &err), 1.5);
  ASSERT_EQ(err.size(), 3u);
  EXPECT_LT(err[1], 1e-6);
  EXPECT_GT(err[0], 10 * err[1] + 1e-6);
  EXPECT_GT(err[2], 10 * err[1] + 1e-6);
  EXPECT_NE(error_of([&] { fit_mls_sigma(g, lp, hp, {}); }).find("no candidates"), std::string::npos);
  EXPECT_NE(error_of([&] { fit_mls_sigma(g, lp, {hp[0]}, {1.0}); }).find("3 LR frames but 1 HR"), std::string::npos);
}

TEST(RbfBaseline, SigmaFitPicksTheGeneratingSigma) {
  const SrGeometry& g = geometry();
  std::vector<std::vector<float>> lr, hr;
  const RbfBaseline truth(g, 2.0);
  for (int f = 0; f < 2; ++f) {
    lr.push_back(smooth_field(g, 0.9 * f));
    hr.push_back(truth.apply(lr.back()));
  }
  const std::vector<const float*> lp = {lr[0].data(), lr[1].data()}, hp = {hr[0].data(), hr[1].data()};
  std::vector<double> err;
  EXPECT_EQ(fit_rbf_sigma(g, lp, hp, {0.8, 2.0, 5.0}, &err), 2.0);
  ASSERT_EQ(err.size(), 3u);
  EXPECT_LT(err[1], 1e-6);
  EXPECT_GT(std::min(err[0], err[2]), 10 * err[1] + 1e-6);

  // Both parameters: truth made at (1.5 cm, μ = 1e-2).
  const RbfBaseline truth2(g, 1.5, 1e-2);
  for (int f = 0; f < 2; ++f) hr[size_t(f)] = truth2.apply(lr[size_t(f)]);
  const std::vector<const float*> hp2 = {hr[0].data(), hr[1].data()};
  const RbfParams p = fit_rbf_params(g, lp, hp2, {1.5, 3.0}, {1e-1, 1e-2}, &err);
  EXPECT_EQ(p.sigma_cm, 1.5);
  EXPECT_EQ(p.regularization, 1e-2);
  ASSERT_EQ(err.size(), 4u);
  EXPECT_LT(err[2], 1e-6);  // μ index 1, σ index 0
  EXPECT_NE(error_of([&] { fit_rbf_params(g, lp, hp2, {1.0}, {}); }).find("no candidates"), std::string::npos);
}
