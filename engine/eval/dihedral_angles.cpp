#include "eval/dihedral_angles.h"

#include <cmath>

namespace facesr {

std::vector<double> oriented_dihedral_angles(const Points& V, const InteriorEdges& edges) {
  std::vector<double> angle(edges.quads.size());
  for (size_t e = 0; e < edges.quads.size(); ++e) {
    const auto& q = edges.quads[e];
    const Vec3 i = V.row(q[0]), j = V.row(q[1]), a = V.row(q[2]), b = V.row(q[3]);
    const Vec3 d = j - i;
    // Unnormalised normals: atan2 of the two projections needs no unit vectors,
    // and their common length factor cancels.
    const Vec3 n1 = d.cross(a - i), n2 = (i - j).cross(b - j);
    const double len = d.norm();
    const double s = len > 0 ? n1.cross(n2).dot(d) / len : 0, c = n1.dot(n2);
    angle[e] = (s == 0 && c == 0) ? 0 : std::atan2(s, c);
  }
  return angle;
}

}  // namespace facesr
