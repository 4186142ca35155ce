#include "eval/voronoi_mass.h"

#include <string>

#include "core/error.h"
#include "eval/cotan_laplacian.h"

namespace facesr {

Eigen::VectorXd voronoi_mass(const Points& V, const Tris& F) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(V.rows());
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k)
      if (!(F(f, k) >= 0 && F(f, k) < V.rows()))
        throw Error("Voronoi mass: triangle " + std::to_string(f) + " refers to vertex " + std::to_string(F(f, k)) +
                    " of " + std::to_string(V.rows()));
    if (degenerate_triangle(V, F, f)) continue;
    const int id[3] = {F(f, 0), F(f, 1), F(f, 2)};
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) p[k] = V.row(id[k]);
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    int obtuse = -1;
    double cot[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
      if (u.dot(w) < 0) obtuse = k;
      cot[k] = u.dot(w) / u.cross(w).norm();
    }
    if (obtuse >= 0) {
      for (int k = 0; k < 3; ++k) m[id[k]] += k == obtuse ? area / 2 : area / 4;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int q = (k + 1) % 3, r = (k + 2) % 3;
      m[id[k]] += ((p[r] - p[k]).squaredNorm() * cot[q] + (p[q] - p[k]).squaredNorm() * cot[r]) / 8;
    }
  }
  return m;
}

}  // namespace facesr
