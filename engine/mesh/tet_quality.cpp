#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "mesh/tet_mesh.h"

namespace facesr {

double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

namespace {
// Dihedral angles at the 6 edges from the 4 outward face normals: the angle
// at the edge shared by faces i and j is pi - angle(n_i, n_j).
void dihedrals(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double out[6]) {
  const Vec3 p[4] = {a, b, c, d};
  Vec3 n[4];
  for (int i = 0; i < 4; ++i) {
    const Vec3& q0 = p[(i + 1) % 4];
    const Vec3& q1 = p[(i + 2) % 4];
    const Vec3& q2 = p[(i + 3) % 4];
    Vec3 nn = (q1 - q0).cross(q2 - q0);
    if (nn.dot(p[i] - q0) > 0) nn = -nn;  // point away from the opposite vertex
    const double len = nn.norm();
    n[i] = len > 0 ? Vec3(nn / len) : Vec3::Zero();
  }
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double c = std::clamp(n[i].dot(n[j]), -1.0, 1.0);
      out[k++] = (M_PI - std::acos(c)) * 180.0 / M_PI;
    }
}
}  // namespace

double tet_min_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  double ang[6];
  dihedrals(a, b, c, d, ang);
  return *std::min_element(ang, ang + 6);
}

TetQuality tet_quality(const TetMesh& m) {
  TetQuality q;
  q.min_dihedral_deg = 180;
  q.max_dihedral_deg = 0;
  q.min_volume = std::numeric_limits<double>::infinity();
  for (int t = 0; t < m.T.rows(); ++t) {
    const Vec3 a = m.X.row(m.T(t, 0)), b = m.X.row(m.T(t, 1)), c = m.X.row(m.T(t, 2)),
               d = m.X.row(m.T(t, 3));
    const double v = tet_signed_volume(a, b, c, d);
    if (!(v > 0)) q.inverted++;
    q.min_volume = std::min(q.min_volume, v);
    q.total_volume += v;
    double ang[6];
    dihedrals(a, b, c, d, ang);
    q.min_dihedral_deg = std::min(q.min_dihedral_deg, *std::min_element(ang, ang + 6));
    q.max_dihedral_deg = std::max(q.max_dihedral_deg, *std::max_element(ang, ang + 6));
  }
  if (m.T.rows() == 0) q.min_volume = 0;
  return q;
}

}  // namespace facesr
