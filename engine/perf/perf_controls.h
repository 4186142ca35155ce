#pragma once
#include "perf/performance.h"
#include "rig/rig.h"
#include "sim/controls.h"

namespace facesr {

// Sets the per-frame controls a performance drives: c.weights from frame
// `frame` (p.names must be the rig's blendshape order) and, when the
// performance has an explicit jaw, c.jaw_override with
//   c.jaw_R = exp(rotation vector in radians),  c.jaw_t = pivot − R·pivot + translation,
// so the jaw turns about jaw.pivot and then shifts. Without one,
// c.jaw_override is false and the jaw follows the jaw blendshapes. Springs,
// spheres and activations are left as they are.
void frame_controls(const Performance& p, int frame, const Jaw& jaw, Controls& c);

// The rigid jaw transform x' = R x + t of one frame's explicit jaw (rotation
// vector in degrees about `pivot`, then translation in cm).
void jaw_rigid_transform(const float* rotation_deg_translation_cm, const Vec3& pivot, Mat3& R, Vec3& t);

}  // namespace facesr
