#include "eval/cotan_laplacian.h"

#include <string>
#include <vector>

#include "core/error.h"

namespace facesr {

bool degenerate_triangle(const Points& V, const Tris& F, int f) {
  const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  const double scale = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return !((b - a).cross(c - a).norm() > 1e-12 * scale);
}

Eigen::SparseMatrix<double> cotan_laplacian(const Points& V, const Tris& F) {
  const long n = V.rows();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(size_t(F.rows()) * 12);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k)
      if (!(F(f, k) >= 0 && F(f, k) < n))
        throw Error("cotangent Laplacian: triangle " + std::to_string(f) + " refers to vertex " +
                    std::to_string(F(f, k)) + " of " + std::to_string(n));
    if (degenerate_triangle(V, F, f)) continue;
    for (int k = 0; k < 3; ++k) {
      // Corner k is opposite the edge (i, j).
      const int o = F(f, k), i = F(f, (k + 1) % 3), j = F(f, (k + 2) % 3);
      const Vec3 u = V.row(i) - V.row(o), w = V.row(j) - V.row(o);
      const double half_cot = 0.5 * u.dot(w) / u.cross(w).norm();
      t.emplace_back(i, j, -half_cot);
      t.emplace_back(j, i, -half_cot);
      t.emplace_back(i, i, half_cot);
      t.emplace_back(j, j, half_cot);
    }
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

}  // namespace facesr
