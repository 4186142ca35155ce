#include "eval/spectral_basis.h"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "eval/cotan_laplacian.h"
#include "eval/voronoi_mass.h"
#include "mesh/tri_mesh.h"

namespace facesr {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// y = (L - sigma M)^-1 x for Spectra. L - sigma M is positive definite for
// sigma < 0, so a sparse LDL^T does what Spectra's own SparseLU wrapper would,
// at a fraction of the cost.
class ShiftInvertLdlt {
 public:
  using Scalar = double;
  ShiftInvertLdlt(const SpMat& L, const SpMat& M) : L_(L), M_(M) {}
  Eigen::Index rows() const { return L_.rows(); }
  Eigen::Index cols() const { return L_.cols(); }
  void set_shift(double sigma) {
    ldlt_.compute(SpMat(L_ - sigma * M_));
    require(ldlt_.info() == Eigen::Success, "spectral basis: factorising L - sigma M failed");
  }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<Eigen::VectorXd>(y, rows()) = ldlt_.solve(Eigen::Map<const Eigen::VectorXd>(x, rows()));
  }

 private:
  const SpMat &L_, &M_;
  Eigen::SimplicialLDLT<SpMat> ldlt_;
};

void solve_dense(const SpMat& L, const Eigen::VectorXd& m, int k, Eigen::VectorXd& values, Eigen::MatrixXd& vecs) {
  // M diagonal: L phi = lambda M phi  <=>  (M^-1/2 L M^-1/2) psi = lambda psi, phi = M^-1/2 psi.
  const Eigen::VectorXd s = m.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd A = s.asDiagonal() * Eigen::MatrixXd(L) * s.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  require(es.info() == Eigen::Success, "spectral basis: the dense eigen solve failed");
  values = es.eigenvalues().head(k);
  vecs = s.asDiagonal() * es.eigenvectors().leftCols(k);
}

void solve_lanczos(const SpMat& L, const Eigen::VectorXd& m, double area, int k, Eigen::VectorXd& values,
                   Eigen::MatrixXd& vecs) {
  const long n = L.rows();
  SpMat M(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (long i = 0; i < n; ++i) t.emplace_back(int(i), int(i), m[i]);
  M.setFromTriplets(t.begin(), t.end());
  // L is singular (constants per component), so shift just below 0. The
  // lowest non-zero eigenvalue of a surface of area A is of order 4 pi^2 / A;
  // a shift of 1e-3 / A keeps L - sigma M well conditioned while the wanted
  // eigenvalues stay far closer to it than the unwanted ones.
  const double sigma = -1e-3 / area;
  ShiftInvertLdlt op(L, M);
  Spectra::SparseSymMatProd<double> bop(M);
  const long ncv = std::min(n, long(std::max(2 * k + 1, k + 32)));
  Spectra::SymGEigsShiftSolver<ShiftInvertLdlt, Spectra::SparseSymMatProd<double>, Spectra::GEigsMode::ShiftInvert>
      solver(op, bop, k, ncv, sigma);
  solver.init();
  solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10, Spectra::SortRule::SmallestAlge);
  require(solver.info() == Spectra::CompInfo::Successful, "spectral basis: the shift-invert Lanczos solve for " +
                                                              std::to_string(k) +
                                                              " eigenvectors did not converge (try a smaller k)");
  values = solver.eigenvalues();
  vecs = solver.eigenvectors();
}

}  // namespace

double SpectralBasis::cutoff_wavelength_cm() const {
  if (k == 0 || !(eigenvalues[k - 1] > 0)) return 0;
  return 2 * M_PI / std::sqrt(eigenvalues[k - 1]);
}

SpectralBasis spectral_basis(const Points& V, const Tris& F, const SpectralOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  SpectralBasis b;
  b.mass = voronoi_mass(V, F);  // validates F against V
  b.area_cm2 = b.mass.sum();
  require(b.area_cm2 > 0 && std::isfinite(b.area_cm2),
          "spectral basis: the surface has no non-degenerate triangle (or a non-finite position)");

  // Vertices in no (non-degenerate) triangle have neither mass nor stiffness;
  // they would make L - sigma M singular, so the problem is solved on the rest.
  std::vector<int> active_index(size_t(V.rows()), -1), active;
  for (int v = 0; v < V.rows(); ++v)
    if (b.mass[v] > 0) {
      active_index[size_t(v)] = int(active.size());
      active.push_back(v);
    }
  const long n = long(active.size());
  b.active_vertices = n;
  require(opt.k >= 1 && opt.k <= n - 1, "spectral basis: k = " + std::to_string(opt.k) + " is outside [1, " +
                                            std::to_string(n - 1) + "] for a surface of " + std::to_string(n) +
                                            " vertices with area");
  b.k = opt.k;

  std::vector<int> tri_ok;
  for (int f = 0; f < F.rows(); ++f)
    if (!degenerate_triangle(V, F, f)) tri_ok.push_back(f);
  Tris Fa(long(tri_ok.size()), 3);
  Points Va(n, 3);
  for (long i = 0; i < n; ++i) Va.row(i) = V.row(active[size_t(i)]);
  for (size_t t = 0; t < tri_ok.size(); ++t)
    for (int c = 0; c < 3; ++c) Fa(long(t), c) = active_index[size_t(F(tri_ok[t], c))];
  face_components(Fa, n, b.components);

  const SpMat L = cotan_laplacian(Va, Fa);
  Eigen::VectorXd m(n);
  for (long i = 0; i < n; ++i) m[i] = b.mass[active[size_t(i)]];

  Eigen::VectorXd values;
  Eigen::MatrixXd vecs;
  if (opt.dense) {
    solve_dense(L, m, opt.k, values, vecs);
    b.solver = "dense";
  } else {
    solve_lanczos(L, m, b.area_cm2, opt.k, values, vecs);
    b.solver = "shift-invert Lanczos (Spectra)";
  }
  // Spectra returns M-normalised vectors already; normalising again costs
  // nothing and makes both paths agree exactly.
  for (int c = 0; c < opt.k; ++c) vecs.col(c) /= std::sqrt(vecs.col(c).dot(m.asDiagonal() * vecs.col(c)));

  b.eigenvalues = values;
  b.vectors = Eigen::MatrixXd::Zero(V.rows(), opt.k);
  for (long i = 0; i < n; ++i) b.vectors.row(active[size_t(i)]) = vecs.row(i);
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

}  // namespace facesr
