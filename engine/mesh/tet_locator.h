#pragma once
#include <vector>

#include "mesh/tet_mesh.h"

namespace facesr {

// Barycentric coordinates of p in tet (a, b, c, d); they sum to one.
Vec4 tet_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Finds the tet containing a point with a uniform grid of tet bounding boxes.
class TetLocator {
 public:
  explicit TetLocator(const TetMesh& mesh, double cell = 0);  // cell 0: from mean tet size
  struct Result {
    int tet = -1;
    Vec4 bary = Vec4::Zero();
    bool inside = false;  // false: nearest tet (least barycentric violation); weights extrapolate
  };
  // Containing tet, or the nearest one among candidates within `search` cm.
  Result locate(const Vec3& p, double search = 0) const;
  const TetMesh& mesh() const { return mesh_; }

 private:
  void candidates(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const;
  const TetMesh& mesh_;
  Vec3 origin_;
  double h_;
  int nx_, ny_, nz_;
  std::vector<int> start_, items_;
};

}  // namespace facesr
