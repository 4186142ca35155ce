#pragma once
#include "core/types.h"

namespace facesr {

struct TetMesh {
  Points X;  // node positions (cm)
  Tets T;    // tetrahedra, positively oriented: det[x1-x0, x2-x0, x3-x0] > 0
};

double tet_signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Smallest of the six interior dihedral angles, in degrees.
double tet_min_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

struct TetQuality {
  double min_dihedral_deg = 0;
  double max_dihedral_deg = 0;
  double min_volume = 0;
  double total_volume = 0;
  long inverted = 0;  // signed volume <= 0
};
TetQuality tet_quality(const TetMesh& m);

}  // namespace facesr
