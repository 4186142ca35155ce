#include "rig/jaw_fit.h"

#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "core/error.h"

namespace facesr {

void fit_rigid(const Points& A, const Points& B, Mat3& R, Vec3& t, double* rms) {
  require(A.rows() == B.rows() && A.rows() >= 3, "fit_rigid: need >= 3 corresponding points");
  const Vec3 ca = A.colwise().mean().transpose(), cb = B.colwise().mean().transpose();
  Mat3 H = Mat3::Zero();
  for (int i = 0; i < A.rows(); ++i) H += (A.row(i).transpose() - ca) * (B.row(i).transpose() - cb).transpose();
  Eigen::JacobiSVD<Mat3> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  R = svd.matrixV() * D * svd.matrixU().transpose();
  t = cb - R * ca;
  if (rms) {
    double s = 0;
    for (int i = 0; i < A.rows(); ++i) s += (R * A.row(i).transpose() + t - B.row(i).transpose()).squaredNorm();
    *rms = std::sqrt(s / A.rows());
  }
}

void hinge_from_rigid(const Mat3& R, const Vec3& t, Vec3& pivot, Vec3& axis, double& angle) {
  Eigen::AngleAxisd aa(R);
  axis = aa.axis();
  angle = aa.angle();
  if (angle < 0) {
    angle = -angle;
    axis = -axis;
  }
  // x' = R (x - p) + p  =>  t = (I - R) p. (I - R) is singular along the
  // axis, so take the minimum-norm solution and keep p off-axis-component free.
  // Its rank must be decided with a threshold: in floating point the null
  // singular value of I − R comes out near 1e-16 rather than 0, and Eigen's
  // default (machine epsilon × size) took that for rank 3 on some heads,
  // putting the pivot 1.8e13 cm down the axis. jawOpen alone does not see
  // that (a rotation about the axis leaves the pivot in place), but every
  // other jaw shape's shift (R_s p + t_s − p) then moved the jaw by
  // kilometres, and the simulation diverged. The nonzero singular values are
  // 2 sin(angle/2): 1e-9 stands for a hinge of under 1e-7 degrees.
  Eigen::CompleteOrthogonalDecomposition<Mat3> cod;
  cod.setThreshold(1e-9);
  cod.compute(Mat3::Identity() - R);
  pivot = cod.solve(t);
}

Vec3 nearest_on_axis(const Vec3& pivot, const Vec3& axis, const Vec3& near) {
  const Vec3 a = axis.normalized();
  return pivot + a.dot(near - pivot) * a;
}

Vec3 hinge_apply(const Vec3& x, const Vec3& pivot, const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis) * (x - pivot) + pivot;
}

}  // namespace facesr
