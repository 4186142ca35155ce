#include "eval/dame.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "eval/dihedral_angles.h"

namespace facesr {
namespace {

double triangle_area(const Points& V, int32_t a, int32_t b, int32_t c) {
  const Vec3 p = V.row(a), q = V.row(b), r = V.row(c);
  return 0.5 * (q - p).cross(r - p).norm();
}

// Area of the two triangles of edge e: (i, j, a) and (j, i, b).
double edge_area(const Points& V, const std::array<int32_t, 4>& q) {
  return triangle_area(V, q[0], q[1], q[2]) + triangle_area(V, q[1], q[0], q[3]);
}

}  // namespace

double dame(const Points& reference, const Points& test, const InteriorEdges& edges, const DameOptions& opt) {
  require(reference.rows() == test.rows(), "DAME: the reference has " + std::to_string(reference.rows()) +
                                               " vertices and the test mesh " + std::to_string(test.rows()));
  require(std::isfinite(opt.masking_rad) && opt.masking_rad >= 0, "DAME: masking_rad must be finite and >= 0");
  for (const auto& q : edges.quads)
    for (const int32_t v : q)
      if (!(v >= 0 && v < reference.rows()))
        throw Error("DAME: an edge refers to vertex " + std::to_string(v) + " of " + std::to_string(reference.rows()));
  const std::vector<double> ref = oriented_dihedral_angles(reference, edges);
  const std::vector<double> tst = oriented_dihedral_angles(test, edges);
  double num = 0, den = 0;
  for (size_t e = 0; e < ref.size(); ++e) {
    const double w = 0.5 * (edge_area(reference, edges.quads[e]) + edge_area(test, edges.quads[e]));
    const double diff = std::abs(std::remainder(ref[e] - tst[e], 2 * M_PI));
    const double m = opt.masking_rad > 0 ? 1 / (1 + std::max(std::abs(ref[e]), std::abs(tst[e])) / opt.masking_rad) : 1;
    num += w * m * diff;
    den += w;
  }
  require(std::isfinite(num) && std::isfinite(den), "DAME: a position is not finite");
  return den > 0 ? num / den : 0;
}

double dame(const Points& reference, const Points& test, const Tris& F, const DameOptions& opt) {
  return dame(reference, test, interior_edges(F, reference.rows()), opt);
}

}  // namespace facesr
