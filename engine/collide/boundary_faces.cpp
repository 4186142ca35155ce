#include "collide/boundary_faces.h"

#include <algorithm>
#include <array>
#include <vector>

namespace facesr {

Tris boundary_faces(const TetMesh& m) {
  struct Face {
    std::array<int32_t, 3> key;  // sorted nodes
    int32_t tet, opposite;       // local index of the vertex not on the face
  };
  std::vector<Face> faces;
  faces.reserve(4 * size_t(m.T.rows()));
  for (int t = 0; t < m.T.rows(); ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int32_t, 3> f;
      for (int i = 0, j = 0; i < 4; ++i)
        if (i != k) f[j++] = m.T(t, i);
      std::sort(f.begin(), f.end());
      faces.push_back({f, t, k});
    }
  std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.key < b.key; });
  std::vector<Vec3i> out;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j == i + 1) {
      const Face& f = faces[i];
      Vec3i tri(f.key[0], f.key[1], f.key[2]);
      const Vec3 a = m.X.row(tri[0]), b = m.X.row(tri[1]), c = m.X.row(tri[2]);
      const Vec3 d = m.X.row(m.T(f.tet, f.opposite));
      if ((b - a).cross(c - a).dot(d - a) > 0) std::swap(tri[1], tri[2]);
      out.push_back(tri);
    }
    i = j;
  }
  Tris F(long(out.size()), 3);
  for (size_t i = 0; i < out.size(); ++i) F.row(long(i)) = out[i].transpose();
  return F;
}

}  // namespace facesr
