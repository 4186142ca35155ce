#pragma once
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "core/types.h"

namespace facesr {

// An Embree BVH over triangles whose vertices move: update() copies new
// positions and refits the BVH (RTC_BUILD_QUALITY_REFIT keeps the topology of
// the tree and only recomputes its bounds, which is what per-Newton-iteration
// collision detection on a deforming skin needs). Closest points and ray
// parities are recomputed in double on the caller's positions. Queries are
// thread-safe between updates.
class DeformingScene {
 public:
  // F indexes a position array of num_vertices points (x, y, z).
  DeformingScene(const Tris& F, int num_vertices);
  ~DeformingScene();
  DeformingScene(const DeformingScene&) = delete;
  DeformingScene& operator=(const DeformingScene&) = delete;

  // x: num_vertices × 3 (cm). The first call builds the BVH, later calls refit.
  void update(const std::vector<double>& x);

  struct Hit {
    int tri = -1;  // -1: nothing within the search radius
    double dist = std::numeric_limits<double>::infinity();
    Vec3 point = Vec3::Zero();
    Vec3 bary = Vec3::Zero();
  };
  // Closest point within max_dist, ignoring triangles for which skip(tri, user) is true.
  using SkipFn = bool (*)(int tri, const void* user);
  Hit closest(const Vec3& p, double max_dist, SkipFn skip = nullptr, const void* user = nullptr) const;
  // Number of triangles crossed by the ray origin + t·dir, t in (0, tmax).
  int crossings(const Vec3& origin, const Vec3& dir, double tmax = std::numeric_limits<double>::infinity()) const;
  // Every triangle crossed by that ray, as (t, triangle), nearest first.
  std::vector<std::pair<double, int>> hits(const Vec3& origin, const Vec3& dir,
                                           double tmax = std::numeric_limits<double>::infinity()) const;

  Vec3 face_normal(int tri) const;  // unit, from the current positions
  const Tris& triangles() const { return F_; }

 private:
  struct Impl;
  Tris F_;
  int nv_;
  std::vector<double> x_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
