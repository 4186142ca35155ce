#include "eval/normal_error.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "mesh/tri_mesh.h"

namespace facesr {

double mean_normal_angle_deg(const Points& reference, const Points& test, const Tris& F) {
  require(reference.rows() == test.rows(), "normal error: the reference has " + std::to_string(reference.rows()) +
                                               " vertices and the test surface " + std::to_string(test.rows()));
  const Points nr = vertex_normals(reference, F), nt = vertex_normals(test, F);
  double sum = 0;
  long count = 0;
  for (int v = 0; v < nr.rows(); ++v) {
    const Vec3 a = nr.row(v), b = nt.row(v);
    if (a.squaredNorm() == 0 || b.squaredNorm() == 0) continue;
    // atan2 of sine and cosine: acos of a dot product near 1 loses the small
    // angles that matter here.
    sum += std::atan2(a.cross(b).norm(), a.dot(b));
    ++count;
  }
  require(std::isfinite(sum), "normal error: a position is not finite");
  return count ? sum / double(count) * 180.0 / M_PI : 0;
}

}  // namespace facesr
