#pragma once
#include <cmath>
#include <limits>

#include <embree3/rtcore.h>

#include "core/types.h"

namespace facesr {

// An Embree ray query origin + t·dir, t in (tnear, tfar), with no hit yet.
inline RTCRayHit embree_ray(const Vec3& o, const Vec3& dir, double tnear, double tfar) {
  RTCRayHit rh;
  rh.ray.org_x = float(o.x());
  rh.ray.org_y = float(o.y());
  rh.ray.org_z = float(o.z());
  rh.ray.dir_x = float(dir.x());
  rh.ray.dir_y = float(dir.y());
  rh.ray.dir_z = float(dir.z());
  rh.ray.tnear = float(tnear);
  rh.ray.tfar = std::isfinite(tfar) ? float(tfar) : std::numeric_limits<float>::infinity();
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFF;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

// An Embree point query at p within `radius` (infinite when not finite).
inline RTCPointQuery embree_point_query(const Vec3& p, double radius) {
  RTCPointQuery q;
  q.x = float(p.x());
  q.y = float(p.y());
  q.z = float(p.z());
  q.time = 0;
  q.radius = std::isfinite(radius) ? float(radius) : std::numeric_limits<float>::infinity();
  return q;
}

}  // namespace facesr
