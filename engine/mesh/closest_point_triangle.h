#pragma once
#include "core/types.h"

namespace facesr {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection,
// section 5.1.5); returns the point and its barycentric coordinates.
Vec3 closest_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* bary);

}  // namespace facesr
