// Finite-difference checks of the Teran material (cl/fsr_material.h):
// energy → stress → stiffness, per term, on normal, degenerate and inverted
// deformation gradients, plus the definiteness fix and the SVD.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "sim/material.h"

using namespace facesr;

namespace {

using Mat9 = Eigen::Matrix<double, 9, 9, Eigen::RowMajor>;
using M3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

struct Case {
  const char* name;
  fsr_material mat;
  double phi, alpha;
};

fsr_material zero_material() { return fsr_material{0, 0, 0, 0.25, 0, 0, 6.6, 1.4}; }

std::vector<Case> cases() {
  const fsr_material full = MaterialParams{}.to_c();
  fsr_material mu10 = zero_material(), mu01 = zero_material(), vol = zero_material(), passive = zero_material(),
               active = zero_material();
  mu10.mu10 = 1.5;
  mu01.mu01 = 0.5;
  vol.kappa = 200;
  passive.sigma_max = 10, passive.p1 = 0.05;
  active.sigma_max = 10;
  return {{"mooney_rivlin_I1", mu10, 0, 0},     {"mooney_rivlin_I2", mu01, 0, 0},
          {"volumetric", vol, 0, 0},            {"fibre_passive", passive, 1, 0},
          {"fibre_active", active, 1, 0.8},     {"full_muscle", full, 0.7, 0.6},
          {"full_flesh", full, 0, 0}};
}

// Deformation gradients of each kind: near-rest stretches, strong
// compression, nearly degenerate (rank ~2), and inverted (det < 0).
std::vector<std::pair<std::string, M3>> gradients() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto rot = [&]() {
    Eigen::Vector3d ax(u(rng), u(rng), u(rng));
    return M3(Eigen::AngleAxisd(2 * u(rng), ax.normalized()).toRotationMatrix());
  };
  std::vector<std::pair<std::string, M3>> out;
  for (int i = 0; i < 4; ++i) {
    M3 F = M3::Identity();
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) += 0.3 * u(rng);
    out.emplace_back("normal" + std::to_string(i), rot() * F);
  }
  out.emplace_back("compressed", M3(rot() * Eigen::Vector3d(0.7, 0.5, 0.35).asDiagonal() * rot()));
  out.emplace_back("stretched", M3(rot() * Eigen::Vector3d(1.5, 1.2, 0.8).asDiagonal() * rot()));
  out.emplace_back("degenerate", M3(rot() * Eigen::Vector3d(1.1, 0.9, 1e-3).asDiagonal() * rot()));
  out.emplace_back("inverted", M3(rot() * Eigen::Vector3d(1.0, 0.8, -0.3).asDiagonal() * rot()));
  out.emplace_back("inverted_strongly", M3(rot() * Eigen::Vector3d(1.3, 0.6, -0.9).asDiagonal() * rot()));
  return out;
}

const double kFibre[3] = {0.48, 0.6, 0.64};  // unit length

double energy(const Case& c, const M3& F) { return fsr_energy_density(&c.mat, F.data(), kFibre, c.phi, c.alpha); }
M3 stress(const Case& c, const M3& F) {
  M3 P;
  fsr_stress(&c.mat, F.data(), kFibre, c.phi, c.alpha, P.data());
  return P;
}
Mat9 dPdF(const Case& c, const M3& F, bool fix) {
  Mat9 C;
  fsr_stress_derivative(&c.mat, F.data(), kFibre, c.phi, c.alpha, fix ? 1 : 0, C.data());
  return C;
}

}  // namespace

TEST(SimMaterial, SvdIsRotationVariant) {
  for (const auto& [name, F] : gradients()) {
    M3 U, V;
    double s[3];
    fsr_svd3(F.data(), U.data(), s, V.data());
    const M3 R = U * Eigen::Vector3d(s[0], s[1], s[2]).asDiagonal() * V.transpose();
    EXPECT_LT((R - F).norm(), 1e-12 * (1 + F.norm())) << name;
    EXPECT_NEAR(U.determinant(), 1.0, 1e-12) << name;
    EXPECT_NEAR(V.determinant(), 1.0, 1e-12) << name;
    EXPECT_LT((U.transpose() * U - M3::Identity()).norm(), 1e-12) << name;
    EXPECT_GE(s[0], s[1]) << name;
    EXPECT_GE(s[1], std::abs(s[2]) - 1e-12) << name;
    EXPECT_EQ(s[2] < 0, F.determinant() < 0) << name;
  }
}

TEST(SimMaterial, StressIsEnergyGradient) {
  for (const auto& c : cases())
    for (const auto& [name, F] : gradients()) {
      const M3 P = stress(c, F);
      const double h = 1e-6;
      M3 fd;
      for (int k = 0; k < 9; ++k) {
        M3 Fp = F, Fm = F;
        Fp(k / 3, k % 3) += h;
        Fm(k / 3, k % 3) -= h;
        fd(k / 3, k % 3) = (energy(c, Fp) - energy(c, Fm)) / (2 * h);
      }
      EXPECT_LT((fd - P).norm(), 1e-6 * (1 + P.norm())) << c.name << " " << name << "\nP=\n" << P << "\nfd=\n" << fd;
    }
}

// The stress comes from the invariants (no SVD); the stiffness works in the
// SVD's diagonal frame. Both must describe the same function: the
// invariant-form P against U P̂(σ) Vᵀ from iso_diag, inverted tets included.
TEST(SimMaterial, InvariantStressMatchesTheDiagonalFrame) {
  for (const auto& c : cases()) {
    if (c.phi != 0) continue;  // the fibre term is the same code in both
    for (const auto& [name, F] : gradients()) {
      M3 U, V;
      double sv[3], Ph[3], H[9], lam[6];
      fsr_svd3(F.data(), U.data(), sv, V.data());
      fsr_iso_diag(&c.mat, sv, Ph, H, lam);
      const M3 Pd = U * Eigen::Vector3d(Ph[0], Ph[1], Ph[2]).asDiagonal() * V.transpose();
      const M3 P = stress(c, F);
      EXPECT_LT((P - Pd).norm(), 1e-11 * (1 + Pd.norm())) << c.name << " " << name << "\nP=\n" << P << "\nPd=\n" << Pd;
    }
  }
}

TEST(SimMaterial, StiffnessIsStressDerivative) {
  for (const auto& c : cases())
    for (const auto& [name, F] : gradients()) {
      const Mat9 C = dPdF(c, F, false);
      const double h = 1e-6;
      Mat9 fd;
      for (int k = 0; k < 9; ++k) {
        M3 Fp = F, Fm = F;
        Fp(k / 3, k % 3) += h;
        Fm(k / 3, k % 3) -= h;
        const M3 dP = (stress(c, Fp) - stress(c, Fm)) / (2 * h);
        for (int r = 0; r < 9; ++r) fd(r, k) = dP(r / 3, r % 3);
      }
      EXPECT_LT((fd - C).norm(), 1e-5 * (1 + C.norm())) << c.name << " " << name;
      EXPECT_LT((C - C.transpose()).norm(), 1e-9 * (1 + C.norm())) << c.name << " " << name;
    }
}

TEST(SimMaterial, DefinitenessFixIsSymmetricPsd) {
  int indefinite_seen = 0;
  for (const auto& c : cases())
    for (const auto& [name, F] : gradients()) {
      const Mat9 C = dPdF(c, F, true);
      EXPECT_LT((C - C.transpose()).norm(), 1e-9 * (1 + C.norm())) << c.name << " " << name;
      const Eigen::SelfAdjointEigenSolver<Mat9> es(0.5 * (C + C.transpose()));
      EXPECT_GE(es.eigenvalues().minCoeff(), -1e-9 * (1 + C.norm())) << c.name << " " << name;
      const Eigen::SelfAdjointEigenSolver<Mat9> raw(dPdF(c, F, false));
      if (raw.eigenvalues().minCoeff() < -1e-9 * (1 + C.norm())) ++indefinite_seen;
      else  // already PSD: the fix must not change it
        EXPECT_LT((C - dPdF(c, F, false)).norm(), 1e-9 * (1 + C.norm())) << c.name << " " << name;
    }
  EXPECT_GT(indefinite_seen, 0) << "the test set should contain indefinite cases for the fix to act on";
}

TEST(SimMaterial, RestIsStressFreeAndStable) {
  const fsr_material mat = MaterialParams{}.to_c();
  const M3 I = M3::Identity();
  M3 P;
  fsr_stress(&mat, I.data(), kFibre, 1.0, 0.0, P.data());
  EXPECT_LT(P.norm(), 1e-12);
  EXPECT_NEAR(fsr_energy_density(&mat, I.data(), kFibre, 1.0, 0.0), 0.0, 1e-12);
  // Small-strain moduli: shear 2(μ10+μ01), bulk κ.
  Mat9 C;
  fsr_stress_derivative(&mat, I.data(), kFibre, 0.0, 0.0, 0, C.data());
  const double mu = 2 * (mat.mu10 + mat.mu01);
  EXPECT_NEAR(C(1, 1) + C(1, 3), 2 * mu, 1e-9);  // δF = e01 + e10: δP01 = 2μ (linear elasticity)
  // With activation the fibre pulls: stress along the fibre is positive (tension).
  fsr_stress(&mat, I.data(), kFibre, 1.0, 1.0, P.data());
  const Eigen::Vector3d a(kFibre[0], kFibre[1], kFibre[2]);
  EXPECT_NEAR(a.dot(P * a), mat.sigma_max, 1e-9);
}

TEST(SimMaterial, ElementForcesAndStiffnessMatchFiniteDifferences) {
  const fsr_material mat = MaterialParams{}.to_c();
  const double X[12] = {0, 0, 0, 1, 0.1, 0, 0.2, 0.9, 0.1, 0.1, 0.2, 1.1};
  M3 Dm;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 3; ++i) Dm(i, c) = X[3 * (c + 1) + i] - X[i];
  const M3 Dminv = Dm.inverse();
  const double vol = Dm.determinant() / 6;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int trial = 0; trial < 3; ++trial) {
    double x[12];
    for (int i = 0; i < 12; ++i) x[i] = X[i] + u(rng);
    if (trial == 2) std::swap(x[0], x[9]), std::swap(x[1], x[10]), std::swap(x[2], x[11]);  // inverted
    auto E = [&](const double* y) {
      double F[9];
      fsr_tet_F(y, Dminv.data(), F);
      return vol * fsr_energy_density(&mat, F, kFibre, 0.8, 0.5);
    };
    auto grad = [&](const double* y, double* g) {
      double F[9], P[9];
      fsr_tet_F(y, Dminv.data(), F);
      fsr_stress(&mat, F, kFibre, 0.8, 0.5, P);
      fsr_tet_scatter(P, Dminv.data(), vol, g);
    };
    double g[12];
    grad(x, g);
    const double h = 1e-6;
    for (int i = 0; i < 12; ++i) {
      double xp[12], xm[12];
      std::copy(x, x + 12, xp);
      std::copy(x, x + 12, xm);
      xp[i] += h;
      xm[i] -= h;
      EXPECT_NEAR(g[i], (E(xp) - E(xm)) / (2 * h), 1e-6 * (1 + std::abs(g[i]))) << "trial " << trial << " dof " << i;
      // Column i of K against the gradient's finite difference.
      double gp[12], gm[12], dx[12] = {0}, Kcol[12], F[9], C[81];
      grad(xp, gp);
      grad(xm, gm);
      dx[i] = 1;
      fsr_tet_F(x, Dminv.data(), F);
      fsr_stress_derivative(&mat, F, kFibre, 0.8, 0.5, 0, C);
      fsr_tet_stiffness_product(C, Dminv.data(), vol, dx, Kcol);
      for (int r = 0; r < 12; ++r)
        EXPECT_NEAR(Kcol[r], (gp[r] - gm[r]) / (2 * h), 1e-5 * (1 + std::abs(Kcol[r]))) << "trial " << trial;
      double D[36];
      fsr_tet_diag_blocks(C, Dminv.data(), vol, D);
      const int k = i / 3, a = i % 3;
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(D[9 * k + 3 * b + a], Kcol[3 * k + b], 1e-9 * (1 + std::abs(Kcol[3 * k + b])));
      // Every block of the assembled form against the product's column.
      double Kb[90];
      fsr_tet_blocks(C, Dminv.data(), vol, Kb);
      for (int r = 0; r < 4; ++r)
        for (int b = 0; b < 3; ++b) {
          const int lo = std::min(r, k), hi = std::max(r, k), pair = lo * (7 - lo) / 2 + hi;
          const double v = r <= k ? Kb[9 * pair + 3 * b + a] : Kb[9 * pair + 3 * a + b];
          EXPECT_NEAR(v, Kcol[3 * r + b], 1e-9 * (1 + std::abs(Kcol[3 * r + b]))) << "block " << r << "," << k;
        }
    }
  }
}
