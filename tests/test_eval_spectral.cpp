// Spectral low/high-frequency split: cotangent Laplacian, mixed Voronoi mass,
// the generalised eigenbasis (M-orthonormal, matching a dense solve, one zero
// eigenvalue per component) and where smooth and noisy error fields land.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

#include "eval/band_split.h"
#include "eval/cotan_laplacian.h"
#include "eval/spectral_basis.h"
#include "eval/voronoi_mass.h"
#include "rig/ict_head.h"
#include "test_support.h"

using namespace facesr;

namespace {

double surface_area(const Points& V, const Tris& F) {
  double a = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const Vec3 p = V.row(F(f, 0)), q = V.row(F(f, 1)), r = V.row(F(f, 2));
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

// An n x n grid over [0, 6]^2 cm, bent into a gentle dome, shifted by `dx` in x.
void grid(int n, double dx, Points& V, Tris& F) {
  V.resize(n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = 6.0 * i / (n - 1), y = 6.0 * j / (n - 1);
      V.row(j * n + i) << x + dx, y, std::exp(-((x - 3) * (x - 3) + (y - 3) * (y - 3)) / 8);
    }
  F.resize(2 * (n - 1) * (n - 1), 3);
  for (int j = 0, f = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      F.row(f++) << a, b, d;
      F.row(f++) << a, d, c;
    }
}

const SpectralBasis& face_basis() {
  static const SpectralBasis b = [] {
    const Rig& rig = fixtures::procedural_rig();
    SpectralBasis s = spectral_basis(rig.surface, rig.surface_tris, {50});
    std::cout << "[ timing ] spectral basis, procedural face (" << rig.surface.rows()
              << " vertices, k = 50): " << s.seconds << " s\n";
    return s;
  }();
  return b;
}

Points random_field(long n, unsigned seed, double sigma) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  Points e(n, 3);
  for (long i = 0; i < n; ++i) e.row(i) << g(rng), g(rng), g(rng);
  return e;
}

}  // namespace

TEST(EvalSpectral, LaplacianAnnihilatesConstantsAndIsSymmetric) {
  const Rig& rig = fixtures::procedural_rig();
  const Eigen::SparseMatrix<double> L = cotan_laplacian(rig.surface, rig.surface_tris);
  ASSERT_EQ(L.rows(), rig.surface.rows());
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(L.rows());
  const double scale = Eigen::VectorXd(L.diagonal()).cwiseAbs().maxCoeff();
  EXPECT_LT((L * one).cwiseAbs().maxCoeff(), 1e-12 * scale);
  const Eigen::SparseMatrix<double> Lt = L.transpose();
  EXPECT_EQ((L - Lt).norm(), 0);
  // Positive semi-definite: x^T L x >= 0 for random x.
  const Eigen::VectorXd x = Eigen::VectorXd::Random(L.rows());
  EXPECT_GT(x.dot(L * x), 0);
}

TEST(EvalSpectral, LaplacianOfALinearFunctionVanishesInsideAFlatGrid) {
  // The cotangent Laplacian is exact on linear functions of a flat mesh away from its border.
  Points V;
  Tris F;
  grid(9, 0, V, F);
  V.col(2).setZero();
  const Eigen::VectorXd u = 2 * V.col(0) - 3 * V.col(1);
  const Eigen::VectorXd Lu = cotan_laplacian(V, F) * u;
  for (int j = 1; j < 8; ++j)
    for (int i = 1; i < 8; ++i) EXPECT_NEAR(Lu[j * 9 + i], 0, 1e-12);
}

TEST(EvalSpectral, MassMatrixSumsToTheSurfaceArea) {
  const Rig& rig = fixtures::procedural_rig();
  const Eigen::VectorXd m = voronoi_mass(rig.surface, rig.surface_tris);
  const double area = surface_area(rig.surface, rig.surface_tris);
  EXPECT_NEAR(m.sum(), area, 1e-9 * area);
  EXPECT_GE(m.minCoeff(), 0);
}

TEST(EvalSpectral, MixedVoronoiAreasOfSingleTriangles) {
  Tris F(1, 3);
  F << 0, 1, 2;
  // Equilateral: the Voronoi regions are thirds.
  Points eq(3, 3);
  eq << 0, 0, 0, 1, 0, 0, 0.5, std::sqrt(3.0) / 2, 0;
  const double a = std::sqrt(3.0) / 4;
  const Eigen::VectorXd me = voronoi_mass(eq, F);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(me[k], a / 3, 1e-14);
  // Obtuse at vertex 2: half the area there, a quarter at each other corner.
  Points ob(3, 3);
  ob << 0, 0, 0, 4, 0, 0, 2, 0.5, 0;
  const Eigen::VectorXd mo = voronoi_mass(ob, F);
  EXPECT_NEAR(mo[2], 0.5, 1e-14);
  EXPECT_NEAR(mo[0], 0.25, 1e-14);
  EXPECT_NEAR(mo[1], 0.25, 1e-14);
  // Right angle at vertex 0 (circumcentre on the hypotenuse): Voronoi formula, 1/4 1/8... summing to the area.
  Points rt(3, 3);
  rt << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  const Eigen::VectorXd mr = voronoi_mass(rt, F);
  EXPECT_NEAR(mr.sum(), 0.5, 1e-14);
  EXPECT_NEAR(mr[0], 0.25, 1e-14);
}

TEST(EvalSpectral, EigenvectorsAreMOrthonormalEigenpairs) {
  const Rig& rig = fixtures::procedural_rig();
  const SpectralBasis& b = face_basis();
  ASSERT_EQ(b.vectors.rows(), rig.surface.rows());
  ASSERT_EQ(b.vectors.cols(), 50);
  const Eigen::MatrixXd G = b.vectors.transpose() * b.mass.asDiagonal() * b.vectors;
  EXPECT_LT((G - Eigen::MatrixXd::Identity(50, 50)).cwiseAbs().maxCoeff(), 1e-8);
  for (int i = 1; i < b.k; ++i) EXPECT_LE(b.eigenvalues[i - 1], b.eigenvalues[i] + 1e-12);
  EXPECT_NEAR(b.eigenvalues[0], 0, 1e-8);
  EXPECT_GT(b.eigenvalues[b.components], 1e-4);  // one zero per component, then the first vibration
  const Eigen::SparseMatrix<double> L = cotan_laplacian(rig.surface, rig.surface_tris);
  const Eigen::MatrixXd R = L * b.vectors - b.mass.asDiagonal() * b.vectors * b.eigenvalues.asDiagonal();
  const Eigen::MatrixXd Mphi = b.mass.asDiagonal() * b.vectors;
  EXPECT_LT(R.norm(), 1e-6 * Mphi.norm() * std::max(1.0, b.eigenvalues.maxCoeff()));
  EXPECT_GT(b.cutoff_wavelength_cm(), 0.5);
  EXPECT_NEAR(b.area_cm2, surface_area(rig.surface, rig.surface_tris), 1e-9 * b.area_cm2);
}

TEST(EvalSpectral, LanczosMatchesADenseSolve) {
  Points V;
  Tris F;
  grid(16, 0, V, F);
  const SpectralBasis it = spectral_basis(V, F, {20});
  SpectralOptions dense_opt{20};
  dense_opt.dense = true;
  const SpectralBasis dn = spectral_basis(V, F, dense_opt);
  EXPECT_EQ(dn.solver, "dense");
  for (int i = 0; i < 20; ++i) EXPECT_NEAR(it.eigenvalues[i], dn.eigenvalues[i], 1e-8 * (1 + dn.eigenvalues[i]));
  // Same subspace: projecting the dense basis onto the iterative one keeps it whole
  // (up to a degenerate pair straddling the cut, which the 19 first avoid on this grid).
  const Eigen::MatrixXd C = it.vectors.transpose() * it.mass.asDiagonal() * dn.vectors.leftCols(18);
  for (int c = 0; c < 18; ++c) EXPECT_NEAR(C.col(c).norm(), 1, 1e-6);
}

TEST(EvalSpectral, EveryComponentHasAZeroEigenvalueAndIsolatedVerticesAreLeftOut) {
  Points A, B;
  Tris FA, FB;
  grid(10, 0, A, FA);
  grid(10, 10, B, FB);
  Points V(A.rows() + B.rows() + 1, 3);
  V << A, B, Eigen::RowVector3d(50, 50, 50);  // the last vertex is in no triangle
  Tris F(FA.rows() + FB.rows(), 3);
  F << FA, (FB.array() + int(A.rows())).matrix();
  const SpectralBasis b = spectral_basis(V, F, {6});
  EXPECT_EQ(b.components, 2);
  EXPECT_EQ(b.active_vertices, V.rows() - 1);
  EXPECT_NEAR(b.eigenvalues[0], 0, 1e-8);
  EXPECT_NEAR(b.eigenvalues[1], 0, 1e-8);
  EXPECT_GT(b.eigenvalues[2], 1e-3);
  EXPECT_EQ(b.vectors.row(V.rows() - 1).norm(), 0);
}

TEST(EvalSpectral, BadKOrEmptySurfaceIsAnError) {
  Points V;
  Tris F;
  grid(4, 0, V, F);
  EXPECT_NE(fixtures::error_of([&] { spectral_basis(V, F, {16}); }).find("k = 16"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { spectral_basis(V, F, {0}); }).find("k = 0"), std::string::npos);
  Points flat = Points::Zero(3, 3);
  Tris one(1, 3);
  one << 0, 1, 2;
  EXPECT_NE(fixtures::error_of([&] { spectral_basis(flat, one, {1}); }).find("no non-degenerate"), std::string::npos);
}

TEST(EvalSpectral, LowFrequencyFieldsLandInTheLowBand) {
  const Rig& rig = fixtures::procedural_rig();
  const SpectralBasis& b = face_basis();
  const long n = rig.surface.rows();
  // A combination of the first eigenvectors is entirely low band.
  Points e(n, 3);
  e.col(0) = 0.3 * b.vectors.col(1) - 0.1 * b.vectors.col(4);
  e.col(1) = 0.2 * b.vectors.col(2);
  e.col(2) = 0.05 * b.vectors.col(9) + 0.02 * b.vectors.col(0);
  const BandSplit s = band_split(b, e);
  EXPECT_GT(s.low_fraction, 1 - 1e-9);
  EXPECT_NEAR(s.low_fraction + s.high_fraction, 1, 1e-12);
  // A smooth function of position (a sideways sag across the face) nearly so.
  Vec3 lo, hi;
  bounding_box(rig.surface, lo, hi);
  Points smooth(n, 3);
  for (long i = 0; i < n; ++i) {
    const double u = (rig.surface(i, 0) - lo.x()) / (hi.x() - lo.x()),
                 w = (rig.surface(i, 1) - lo.y()) / (hi.y() - lo.y());
    smooth.row(i) << 0.1 * std::sin(M_PI * u), 0.05 * u * w, -0.2 * w * w;
  }
  const BandSplit ss = band_split(b, smooth);
  EXPECT_GT(ss.low_fraction, 0.97);
  EXPECT_NEAR(ss.low_fraction + ss.high_fraction, 1, 1e-12);
  // The low band is what the projection gives: its M-norm is the low energy.
  const Points low = low_band(b, smooth);
  EXPECT_NEAR((low.array() * (b.mass.asDiagonal() * low).array()).sum(), ss.low_energy, 1e-9 * ss.low_energy);
}

TEST(EvalSpectral, PerVertexNoiseLandsInTheHighBand) {
  const SpectralBasis& b = face_basis();
  const BandSplit s = band_split(b, random_field(b.num_vertices(), 7, 0.05));
  EXPECT_GT(s.high_fraction, 0.85);
  EXPECT_NEAR(s.low_fraction + s.high_fraction, 1, 1e-12);
  EXPECT_GT(s.high_rms_cm, 2 * s.low_rms_cm);
}

TEST(EvalSpectral, ATranslationIsAllLowBandWithItsLengthAsRms) {
  const SpectralBasis& b = face_basis();
  Points e(b.num_vertices(), 3);
  e.rowwise() = Eigen::RowVector3d(0.3, 0, 0.4);  // 0.5 cm everywhere
  const BandSplit s = band_split(b, e);
  EXPECT_NEAR(s.low_fraction, 1, 1e-9);
  EXPECT_NEAR(s.low_rms_cm, 0.5, 1e-9);
  EXPECT_NEAR(s.high_rms_cm, 0, 1e-4);
  // Zero error: no energy, both fractions 0.
  const BandSplit z = band_split(b, Points::Zero(b.num_vertices(), 3));
  EXPECT_EQ(z.low_fraction + z.high_fraction, 0);
  // Accumulating two frames weighs them by their energy.
  const BandSplit acc = accumulate({s, band_split(b, random_field(b.num_vertices(), 3, 0.5))}, b.area_cm2);
  EXPECT_NEAR(acc.low_fraction + acc.high_fraction, 1, 1e-12);
  EXPECT_LT(acc.low_fraction, 0.5);
}

TEST(EvalSpectral, FieldOfTheWrongSizeIsAnError) {
  const SpectralBasis& b = face_basis();
  EXPECT_NE(fixtures::error_of([&] { band_split(b, Points::Zero(5, 3)); }).find("5 vertices"), std::string::npos);
  Points e = Points::Zero(b.num_vertices(), 3);
  e(3, 1) = std::nan("");
  EXPECT_NE(fixtures::error_of([&] { band_split(b, e); }).find("non-finite"), std::string::npos);
}

TEST(EvalSpectral, DefaultKOnTheProceduralFaceIsQuick) {
  const Rig& rig = fixtures::procedural_rig();
  const SpectralBasis b = spectral_basis(rig.surface, rig.surface_tris);
  EXPECT_EQ(b.k, 100);
  std::cout << "[ timing ] spectral basis, procedural face (" << rig.surface.rows()
            << " vertices, default k = 100): " << b.seconds << " s, lambda_k = " << b.eigenvalues[99]
            << " /cm^2, cutoff wavelength " << b.cutoff_wavelength_cm() << " cm, area " << b.area_cm2 << " cm^2, "
            << b.components << " component(s)\n";
  EXPECT_LT(b.seconds, 30);
}

TEST(EvalSpectral, DefaultBasisOnTheIctFace) {
  if (!fixtures::have_ict()) GTEST_SKIP() << "no ICT FaceKit data at " << fixtures::ict_dir();
  // The face surface as rig_build() cuts it from the skin: the face vertices
  // and the skin triangles among them.
  const HeadSource h = load_ict_head(fixtures::ict_dir(), false);
  std::vector<int> of_skin(size_t(h.skin.V.rows()), -1);
  Points V(long(h.face_vertices.size()), 3);
  for (size_t i = 0; i < h.face_vertices.size(); ++i) {
    of_skin[size_t(h.face_vertices[i])] = int(i);
    V.row(long(i)) = h.skin.V.row(h.face_vertices[i]);
  }
  std::vector<Vec3i> tris;
  for (int f = 0; f < h.skin.F.rows(); ++f) {
    const int a = of_skin[size_t(h.skin.F(f, 0))], b = of_skin[size_t(h.skin.F(f, 1))],
              c = of_skin[size_t(h.skin.F(f, 2))];
    if (a >= 0 && b >= 0 && c >= 0) tris.emplace_back(a, b, c);
  }
  Tris F(long(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) F.row(long(t)) = tris[t].cast<int32_t>().transpose();

  const SpectralBasis b = spectral_basis(V, F);
  std::cout << "[ timing ] spectral basis, ICT face (" << V.rows() << " vertices, " << F.rows()
            << " triangles, default k = 100): " << b.seconds << " s, cutoff wavelength " << b.cutoff_wavelength_cm()
            << " cm, area " << b.area_cm2 << " cm^2\n";
  const Eigen::MatrixXd G = b.vectors.transpose() * b.mass.asDiagonal() * b.vectors;
  EXPECT_LT((G - Eigen::MatrixXd::Identity(b.k, b.k)).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_NEAR(b.eigenvalues[0], 0, 1e-8);
  EXPECT_GT(b.eigenvalues[b.components], 1e-4);
  EXPECT_LT(b.seconds, 60);
}
