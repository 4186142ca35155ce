#pragma once
#include "core/types.h"
#include "rig/rig.h"

namespace facesr {

// Least-squares rigid transform (Kabsch) taking points A to B: B ≈ R A + t.
void fit_rigid(const Points& A, const Points& B, Mat3& R, Vec3& t, double* rms = nullptr);

// Hinge (axis through pivot, angle) closest to a rigid transform: the
// rotation axis and angle of R, and the point on the axis that minimises
// |(R - I)(x - p) - (t + (R - I) x)| in least squares. Returns the axis
// oriented so that the angle is positive.
void hinge_from_rigid(const Mat3& R, const Vec3& t, Vec3& pivot, Vec3& axis, double& angle_rad);

// How far (cm) a jaw pivot may sit along its axis from the point beside the
// lower teeth before the rig builder moves it there (see fit_jaw).
constexpr double kJawPivotSlackCm = 5.0;
// Beyond this distance (cm) from the lower teeth a rig's pivot is the
// degenerate hinge fit of facesr before 2026-12-04, and the rig is refused.
constexpr double kJawPivotMaxCm = 100.0;

// The point on the axis through `pivot` closest to `near`.
Vec3 nearest_on_axis(const Vec3& pivot, const Vec3& axis, const Vec3& near);

// Rotation by `angle_rad` about `axis` through `pivot`, applied to x.
Vec3 hinge_apply(const Vec3& x, const Vec3& pivot, const Vec3& axis, double angle_rad);

}  // namespace facesr
