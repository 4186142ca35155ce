#pragma once
#include <limits>
#include <memory>
#include <vector>

#include "core/types.h"

namespace facesr {

// Closest-point and ray queries on a triangle mesh, accelerated by an Embree
// BVH. Embree traverses in float; distances and closest points are recomputed
// in double on the caller's arrays.
class SurfaceQuery {
 public:
  SurfaceQuery(const Points& V, const Tris& F);
  ~SurfaceQuery();
  SurfaceQuery(const SurfaceQuery&) = delete;
  SurfaceQuery& operator=(const SurfaceQuery&) = delete;

  struct Closest {
    double dist = std::numeric_limits<double>::infinity();
    Vec3 point = Vec3::Zero();
    Vec3 bary = Vec3::Zero();
    int tri = -1;  // -1 when nothing lies within max_dist
  };
  Closest closest(const Vec3& p, double max_dist = std::numeric_limits<double>::infinity()) const;

  struct RayHit {
    double t = 0;
    int tri = -1;
    Vec3 bary = Vec3::Zero();
  };
  // First hit along origin + t*dir for t in (tmin, tmax); tri = -1 if none.
  RayHit first_hit(const Vec3& origin, const Vec3& dir, double tmin, double tmax) const;
  // All hits along the ray, sorted by t.
  std::vector<double> all_hits(const Vec3& origin, const Vec3& dir, double tmax) const;

  const Points& vertices() const { return V_; }
  const Tris& triangles() const { return F_; }

 private:
  struct Impl;
  Points V_;
  Tris F_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
