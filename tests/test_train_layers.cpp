// The LibTorch layers of the super-resolution network: finite-difference
// gradient checks in double precision on a tiny graph, parity of the
// algebraic shortcuts with the straightforward formulas, and parameter names
// that match the architecture.
#include <gtest/gtest.h>

#include <random>

#include "sr/sr_architecture.h"
#include "train/edge_conv.h"
#include "train/lr_schedule.h"
#include "train/sr_loss.h"
#include "train/sr_network.h"
#include "train/vae_network.h"

namespace facesr {
namespace {

// A tiny synthetic geometry: N LR nodes, M HR vertices, random neighbours.
SrGeometry tiny_geometry(int N, int M, int graph_k, int up_k, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  SrGeometry g;
  g.num_lr = N;
  g.num_hr = M;
  g.graph_k = graph_k;
  g.upsample_k = up_k;
  for (int i = 0; i < 3 * N; ++i) g.lr_rest.push_back(2 * u(rng));
  for (int i = 0; i < 3 * M; ++i) g.hr_rest.push_back(2 * u(rng));
  auto distinct = [&](int count, int n, int skip) {
    std::vector<int> all;
    for (int i = 0; i < n; ++i)
      if (i != skip) all.push_back(i);
    std::shuffle(all.begin(), all.end(), rng);
    all.resize(size_t(count));
    return all;
  };
  for (int i = 0; i < N; ++i)
    for (int j : distinct(graph_k, N, i)) g.lr_graph.push_back(j);
  g.lr_to_hr.assign(size_t(N), -1);
  for (int j = 0; j < M; ++j) {
    for (int i : distinct(up_k, N, -1)) {
      g.up_index.push_back(i);
      g.up_dist.push_back(1.0f + u(rng) * 0.5f);
    }
    for (int i : distinct(up_k, N, -1)) {
      g.euclid_index.push_back(i);
      g.euclid_dist.push_back(1.0f);
    }
  }
  return g;
}

SrArchitecture tiny_arch() {
  SrArchitecture a;
  a.pe_dim = 4;
  a.encoder_dims = {5, 6};
  a.graph_k = 2;
  a.upsample_k = 3;
  a.weight_hidden = {4};
  a.recon_hidden = {6, 5};
  a.omega0 = 3;  // smaller than SIREN's 30 so central differences resolve the sines
  return a;
}

// Central-difference check of d(loss)/d(tensor) at a few random entries.
template <class LossFn>
void check_gradient(torch::Tensor t, LossFn loss_fn, const std::string& what, int probes = 12) {
  if (t.grad().defined()) t.grad().zero_();
  loss_fn().backward();
  const auto g = t.grad().clone();
  std::mt19937 rng(7);
  const int64_t n = t.numel();
  double max_rel = 0;
  for (int p = 0; p < probes; ++p) {
    const int64_t i = std::uniform_int_distribution<int64_t>(0, n - 1)(rng);
    const double h = 1e-6;
    double fp, fm;
    {
      torch::NoGradGuard ng;
      auto flat = t.view({-1});
      const double v = flat[i].item<double>();
      flat[i] = v + h;
      fp = loss_fn().template item<double>();
      flat[i] = v - h;
      fm = loss_fn().template item<double>();
      flat[i] = v;
    }
    const double fd = (fp - fm) / (2 * h);
    const double an = g.view({-1})[i].item<double>();
    const double rel = std::abs(fd - an) / std::max(1e-6, std::abs(fd) + std::abs(an));
    max_rel = std::max(max_rel, rel);
    EXPECT_LT(rel, 1e-5) << what << " entry " << i << ": finite difference " << fd << ", autograd " << an;
  }
  EXPECT_LT(max_rel, 1e-5) << what;
}

TEST(TrainLayers, EdgeConvMatchesTheDirectFormulaAndItsGradient) {
  torch::manual_seed(3);
  const int64_t B = 2, N = 7, k = 3, Din = 4, Dout = 5;
  EdgeConvBlock block(Din, Dout, 0.2);
  block->to(torch::kFloat64);
  auto h = torch::randn({B, N, Din}, torch::kFloat64).requires_grad_(true);
  auto nbr = torch::randint(0, N, {B, N, k}, torch::kLong);
  // Straightforward EdgeConv: LeakyReLU(Θ [h_i, h_j − h_i] + b), max over j.
  auto params = block->named_parameters();
  const auto W = *params.find("edge.weight"), b = *params.find("edge.bias");
  auto direct = torch::full({B, N, Dout}, -1e300, torch::kFloat64);
  for (int64_t bi = 0; bi < B; ++bi)
    for (int64_t i = 0; i < N; ++i)
      for (int64_t q = 0; q < k; ++q) {
        const auto hj = h[bi][nbr[bi][i][q].item<int64_t>()];
        const auto e = torch::cat({h[bi][i], hj - h[bi][i]});
        const auto y = torch::leaky_relu(torch::matmul(W, e) + b, 0.2);
        direct[bi][i] = torch::maximum(direct[bi][i], y);
      }
  EXPECT_LT((block->edge(h, nbr) - direct).abs().max().item<double>(), 1e-12);
  // The block's shared FC on [y, global max, global average, input], as written.
  const auto gmax = direct.amax(1, true).expand({B, N, Dout}), gavg = direct.mean(1, true).expand({B, N, Dout});
  const auto full = torch::leaky_relu(
      torch::linear(torch::cat({direct, gmax, gavg, h}, 2), *params.find("fc.weight"), *params.find("fc.bias")), 0.2);
  EXPECT_LT((block->forward(h, nbr) - full).abs().max().item<double>(), 1e-12);

  const auto proj = torch::randn({B, N, Dout}, torch::kFloat64);
  auto loss = [&] { return (block->forward(h, nbr) * proj).sum(); };
  check_gradient(h, loss, "EdgeConv block input");
  check_gradient(*params.find("edge.weight"), loss, "EdgeConv edge weight");
  check_gradient(*params.find("fc.weight"), loss, "EdgeConv shared FC weight");
}

TEST(TrainLayers, FeatureKnnFindsTheNearestOtherNodes) {
  // Points on a line: the neighbours of x are the nodes at the next distances.
  auto h = torch::tensor({0.0f, 1.0f, 3.0f, 7.0f, 15.0f}).view({1, 5, 1});
  const auto nn = feature_knn(h, 2);
  const std::vector<std::vector<int64_t>> expect{{1, 2}, {0, 2}, {1, 0}, {2, 1}, {3, 2}};
  for (int i = 0; i < 5; ++i)
    for (int q = 0; q < 2; ++q) EXPECT_EQ(nn[0][i][q].item<int64_t>(), expect[size_t(i)][size_t(q)]) << i;
}

TEST(TrainLayers, NetworkGradientMatchesFiniteDifferences) {
  torch::manual_seed(5);
  const SrGeometry g = tiny_geometry(9, 11, 2, 3, 11);
  SrArchitecture a = tiny_arch();
  set_coordinate_frame(a, g);
  SrNetwork net(a, g);
  net->to(torch::kFloat64);
  const auto lr = torch::randn({2, 9, 3}, torch::kFloat64) * 0.3;
  const auto target = torch::randn({2, 11, 3}, torch::kFloat64) * 0.3;
  const auto rest = torch::randn({11, 3}, torch::kFloat64);
  const auto tris = torch::tensor({0, 1, 2, 2, 3, 4, 5, 6, 7, 7, 8, 9}, torch::kLong).view({4, 3});
  auto loss = [&] {
    auto out = net->forward(lr);
    // A smooth stand-in for the L1 term (|x| has a kink at 0), plus the
    // normal and feature terms as trained.
    auto t = sr_loss(out.hr_disp, target, rest, tris, out.features, 0.1, 0.01);
    return (out.hr_disp - target).pow(2).sum() + 0.1 * t.normal + 0.01 * t.reg;
  };
  auto params = net->named_parameters();
  for (const char* name : {"encoder.0.edge.weight", "encoder.1.fc.weight", "weight_net.0.weight",
                           "weight_net.1.weight", "recon.0.weight", "recon.2.bias"})
    { SCOPED_TRACE(name); check_gradient(*params.find(name), loss, name); }
}

TEST(TrainLayers, UpsamplingShortcutsEqualTheStraightforwardNetwork) {
  // The network applies the reconstruction's first affine map before the
  // interpolation (exact because the weights sum to one); compare with
  // interpolating the encoded features first.
  torch::manual_seed(9);
  const SrGeometry g = tiny_geometry(10, 13, 2, 4, 21);
  for (bool cu : {true, false}) {
    SrArchitecture a = tiny_arch();
    a.upsample_k = 4;
    a.coordinate_upsampling = cu;
    set_coordinate_frame(a, g);
    SrNetwork net(a, g);
    net->to(torch::kFloat64);
    if (!cu) {
      torch::NoGradGuard ng;
      net->named_parameters().find("free_weights")->normal_();
    }
    const auto lr = torch::randn({3, 10, 3}, torch::kFloat64);
    const auto fast = net->forward(lr).hr_disp;
    const auto z = net->encode(lr);
    const auto w = net->upsample_weights();
    EXPECT_LT((w.sum(1) - 1).abs().max().item<double>(), 1e-12);
    const auto idx = net->upsample_index();
    auto zh = torch::zeros({3, 13, z.size(2)}, torch::kFloat64);
    for (int64_t j = 0; j < 13; ++j)
      for (int64_t q = 0; q < 4; ++q) zh.select(1, j) += w[j][q] * z.select(1, idx[j][q].item<int64_t>());
    auto params = net->named_parameters();
    auto x = torch::sin(a.omega0 * torch::linear(zh, *params.find("recon.0.weight"), *params.find("recon.0.bias")));
    x = torch::sin(a.omega0 * torch::linear(x, *params.find("recon.1.weight"), *params.find("recon.1.bias")));
    const auto slow = torch::linear(x, *params.find("recon.2.weight"), *params.find("recon.2.bias")) * a.output_scale;
    EXPECT_LT((fast - slow).abs().max().item<double>(), 1e-10) << (cu ? "with CU" : "without CU");
  }
}

TEST(TrainLayers, ParameterNamesAndShapesMatchTheArchitecture) {
  const SrGeometry g = tiny_geometry(9, 11, 2, 3, 1);
  auto check = [&](torch::nn::Module& m, const SrArchitecture& a) {
    const auto expected = parameter_shapes(a, 9, 11);
    auto params = m.named_parameters(true);
    ASSERT_EQ(params.size(), expected.size());
    for (const auto& [name, shape] : expected) {
      const auto* p = params.find(name);
      ASSERT_NE(p, nullptr) << name;
      EXPECT_EQ(p->sizes().vec(), shape) << name;
    }
  };
  for (int variant = 0; variant < 3; ++variant) {
    SrArchitecture a = tiny_arch();
    a.feature_encoding = variant != 1;
    a.coordinate_upsampling = variant != 2;
    SrNetwork net(a, g);
    check(*net, a);
    EXPECT_EQ(net->encode(torch::zeros({1, 9, 3})).size(2), a.encoded_dim());
  }
  SrArchitecture v;
  v.kind = "vae";
  v.vae_encoder = {8, 6};
  v.vae_latent = 3;
  v.vae_decoder = {4, 5};
  VaeNetwork vae(v, 9, 11);
  check(*vae, v);
  EXPECT_EQ(vae->forward(torch::zeros({2, 9, 3}), false).hr_disp.sizes().vec(), (std::vector<int64_t>{2, 11, 3}));
}

TEST(TrainLayers, LossTermsOnHandMadeCases) {
  // One right triangle; the prediction rotates it 90° about x: normals
  // orthogonal, so the normal term is 1; L1 is the sum of |differences|.
  const auto rest = torch::tensor({0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}).view({3, 3});
  const auto tris = torch::tensor({0, 1, 2}, torch::kLong).view({1, 3});
  const auto target = torch::zeros({1, 3, 3});
  auto pred = torch::zeros({1, 3, 3});
  pred[0][2] = torch::tensor({0.0f, -1.0f, 1.0f});  // vertex 2 moves from (0,1,0) to (0,0,1)
  const std::vector<torch::Tensor> feats{torch::ones({1, 2, 4})};  // two nodes with ‖z‖ = 2
  const auto t = sr_loss(pred, target, rest, tris, feats, 0.5, 0.25);
  EXPECT_NEAR(t.recon.item<double>(), 2.0, 1e-6);
  EXPECT_NEAR(t.normal.item<double>(), 1.0, 1e-6);
  EXPECT_NEAR(t.reg.item<double>(), 4.0, 1e-6);
  EXPECT_NEAR(t.total.item<double>(), (2.0 + 0.5 * 1.0 + 0.25 * 4.0) / 3, 1e-6);
  EXPECT_DOUBLE_EQ(beta_schedule(0, 11, 1e-3, 20), 1e-3);
  EXPECT_NEAR(beta_schedule(10, 11, 1e-3, 20), 20, 1e-9);
  EXPECT_NEAR(beta_schedule(5, 11, 1e-3, 20), std::sqrt(1e-3 * 20), 1e-9);
}

TEST(TrainLayers, RelativeFrameWeightsFollowTheCorrectionSize) {
  // Two frames of two vertices: frame 0's HR target is 3 cm from the
  // embedded surface at each vertex (mean 3), frame 1's 0.5 cm at one
  // vertex (mean 0.25).
  auto hr = torch::zeros({2, 2, 3}), emb = torch::zeros({2, 2, 3});
  hr[0][0][0] = 3.0f;
  hr[0][1][1] = 3.0f;
  hr[1][0][2] = 0.5f;
  const double floor_cm = 0.25;
  const auto w = relative_frame_weights(hr, emb, floor_cm);
  ASSERT_EQ(w.size(0), 2);
  // ∝ 1/3.25 and 1/0.5, mean 1.
  const double a = 1 / 3.25, b = 1 / 0.5, m = (a + b) / 2;
  EXPECT_NEAR(w[0].item<double>(), a / m, 1e-6);
  EXPECT_NEAR(w[1].item<double>(), b / m, 1e-6);

  // In the loss they scale each frame's L1 term; unit weights give the paper's loss.
  const auto rest = torch::tensor({0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f}).view({2, 3});
  const auto no_tris = torch::zeros({0, 3}, torch::kLong);
  const auto pred = torch::zeros({2, 2, 3});
  const auto plain = sr_loss(pred, hr, rest, no_tris, {}, 0, 0);
  const auto ones = sr_loss(pred, hr, rest, no_tris, {}, 0, 0, torch::ones({2}));
  EXPECT_NEAR(plain.recon.item<double>(), (6.0 + 0.5) / 2, 1e-6);
  EXPECT_NEAR(ones.recon.item<double>(), plain.recon.item<double>(), 1e-6);
  const auto weighted = sr_loss(pred, hr, rest, no_tris, {}, 0, 0, w);
  EXPECT_NEAR(weighted.recon.item<double>(), (6.0 * a / m + 0.5 * b / m) / 2, 1e-5);
}

TEST(TrainSchedule, CosineLearningRateRunsFromStartToFinalAndIsConstantWhenUnset) {
  EXPECT_DOUBLE_EQ(learning_rate_schedule(0, 11, 1e-3, 1e-5), 1e-3);
  EXPECT_DOUBLE_EQ(learning_rate_schedule(10, 11, 1e-3, 1e-5), 1e-5);
  EXPECT_NEAR(learning_rate_schedule(5, 11, 1e-3, 1e-5), 0.5 * (1e-3 + 1e-5), 1e-15);
  for (int e = 1; e < 11; ++e)
    EXPECT_LT(learning_rate_schedule(e, 11, 1e-3, 1e-5), learning_rate_schedule(e - 1, 11, 1e-3, 1e-5));
  EXPECT_DOUBLE_EQ(learning_rate_schedule(7, 11, 1e-3, 0), 1e-3);
  EXPECT_DOUBLE_EQ(learning_rate_schedule(0, 1, 1e-3, 1e-5), 1e-3);
}

}  // namespace
}  // namespace facesr
