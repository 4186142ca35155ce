#pragma once
#include <memory>
#include <vector>

#include "mesh/grid.h"
#include "mesh/surface_query.h"
#include "rig/head_source.h"
#include "rig/rig.h"

namespace facesr {

// Soft-tissue thickness (cm) under the skin, interpolated from landmark
// samples of facial soft-tissue depth.
class ThicknessField {
 public:
  explicit ThicknessField(const HeadSource& src);
  double at(const Vec3& p) const;

 private:
  std::vector<Vec3> pos_;
  std::vector<double> depth_;
};

// The flesh between the closed skin surface and the bone, which lies deeper
// than the local soft-tissue thickness: flesh = {-t(x) < sd(x) < 0}. Also
// holds the jaw skinning weight of every skin vertex.
class FleshDomain {
 public:
  FleshDomain(const HeadSource& src, const Jaw& jaw, double grid_h, bool verbose);

  // Signed distance to the skin (negative inside), trilinear on the grid.
  double sd(const Vec3& p) const;
  // Bone indicator sd + t: negative inside bone.
  double bone(const Vec3& p) const;
  bool in_flesh(const Vec3& p) const { return sd(p) < 0 && bone(p) > 0; }
  // Jaw skinning weight at p, interpolated from the nearest skin point.
  double jaw_weight(const Vec3& p) const;
  // Nearest skin vertex (by closest triangle, its nearest corner).
  int nearest_skin_vertex(const Vec3& p) const;

  // Closed bone surface(s), remeshed; normals point out of the bone.
  TriMesh bone_surface(double edge, bool verbose) const;

  const std::vector<double>& skin_jaw_weight() const { return skin_w_; }
  const SurfaceQuery& skin_query() const { return *skin_q_; }
  const Grid& grid() const { return grid_; }

 private:
  double trilinear(const std::vector<float>& f, const Vec3& p) const;
  const HeadSource& src_;
  Grid grid_;
  std::vector<float> sd_, bone_;
  std::unique_ptr<SurfaceQuery> skin_q_;
  std::vector<double> skin_w_;
};

// Predeformation of the LR rest pose: hinge rotation weighted by the jaw
// weight, and its (first-order) inverse.
Vec3 predeform_point(const Vec3& x, double w, const Jaw& jaw, double angle_deg);

}  // namespace facesr
