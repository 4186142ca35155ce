#include "mesh/tet_locator.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace facesr {

Vec4 tet_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Mat3 M;
  M.col(0) = b - a;
  M.col(1) = c - a;
  M.col(2) = d - a;
  const Vec3 x = M.partialPivLu().solve(p - a);
  return Vec4(1.0 - x.sum(), x[0], x[1], x[2]);
}

TetLocator::TetLocator(const TetMesh& mesh, double cell) : mesh_(mesh) {
  const Vec3 lo = mesh.X.colwise().minCoeff().transpose();
  const Vec3 hi = mesh.X.colwise().maxCoeff().transpose();
  if (cell <= 0) {
    const double vol = std::max(1e-12, (hi - lo).prod());
    cell = 2.0 * std::cbrt(vol / std::max<long>(1, mesh.T.rows()));
  }
  h_ = cell;
  origin_ = lo - Vec3::Constant(1e-6);
  nx_ = std::max(1, int(std::ceil((hi.x() - origin_.x()) / h_)) + 1);
  ny_ = std::max(1, int(std::ceil((hi.y() - origin_.y()) / h_)) + 1);
  nz_ = std::max(1, int(std::ceil((hi.z() - origin_.z()) / h_)) + 1);
  const long ncell = long(nx_) * ny_ * nz_;
  std::vector<int> count(ncell + 1, 0);
  auto for_cells = [&](int t, auto&& fn) {
    Vec3 tlo = mesh.X.row(mesh.T(t, 0)).transpose(), thi = tlo;
    for (int k = 1; k < 4; ++k) {
      tlo = tlo.cwiseMin(mesh.X.row(mesh.T(t, k)).transpose());
      thi = thi.cwiseMax(mesh.X.row(mesh.T(t, k)).transpose());
    }
    const int i0 = std::clamp(int((tlo.x() - origin_.x()) / h_), 0, nx_ - 1);
    const int j0 = std::clamp(int((tlo.y() - origin_.y()) / h_), 0, ny_ - 1);
    const int k0 = std::clamp(int((tlo.z() - origin_.z()) / h_), 0, nz_ - 1);
    const int i1 = std::clamp(int((thi.x() - origin_.x()) / h_), 0, nx_ - 1);
    const int j1 = std::clamp(int((thi.y() - origin_.y()) / h_), 0, ny_ - 1);
    const int k1 = std::clamp(int((thi.z() - origin_.z()) / h_), 0, nz_ - 1);
    for (int k = k0; k <= k1; ++k)
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) fn((long(k) * ny_ + j) * nx_ + i);
  };
  for (int t = 0; t < mesh.T.rows(); ++t) for_cells(t, [&](long c) { count[c + 1]++; });
  for (long c = 0; c < ncell; ++c) count[c + 1] += count[c];
  start_ = count;
  items_.resize(start_[ncell]);
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int t = 0; t < mesh.T.rows(); ++t) for_cells(t, [&](long c) { items_[fill[c]++] = t; });
}

void TetLocator::candidates(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const {
  out.clear();
  const int i0 = std::clamp(int(std::floor((lo.x() - origin_.x()) / h_)), 0, nx_ - 1);
  const int j0 = std::clamp(int(std::floor((lo.y() - origin_.y()) / h_)), 0, ny_ - 1);
  const int k0 = std::clamp(int(std::floor((lo.z() - origin_.z()) / h_)), 0, nz_ - 1);
  const int i1 = std::clamp(int(std::floor((hi.x() - origin_.x()) / h_)), 0, nx_ - 1);
  const int j1 = std::clamp(int(std::floor((hi.y() - origin_.y()) / h_)), 0, ny_ - 1);
  const int k1 = std::clamp(int(std::floor((hi.z() - origin_.z()) / h_)), 0, nz_ - 1);
  for (int k = k0; k <= k1; ++k)
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const long c = (long(k) * ny_ + j) * nx_ + i;
        out.insert(out.end(), items_.begin() + start_[c], items_.begin() + start_[c + 1]);
      }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

TetLocator::Result TetLocator::locate(const Vec3& p, double search) const {
  std::vector<int> cand;
  Result best;
  double best_violation = 1e300;
  candidates(p - Vec3::Constant(search), p + Vec3::Constant(search), cand);
  for (int t : cand) {
    const auto& X = mesh_.X;
    const auto& T = mesh_.T;
    const Vec4 b = tet_barycentric(p, X.row(T(t, 0)), X.row(T(t, 1)), X.row(T(t, 2)), X.row(T(t, 3)));
    const double violation = -std::min(0.0, b.minCoeff());
    if (violation < best_violation) {
      best_violation = violation;
      best.tet = t;
      best.bary = b;
    }
    if (violation <= 1e-10) break;
  }
  if (best.tet >= 0) {
    best.inside = best_violation <= 1e-9;
    // Outside points keep their (affine) barycentric weights: extrapolating
    // from the nearest tet still reproduces the rest position exactly.
  }
  return best;
}

}  // namespace facesr
