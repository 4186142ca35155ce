#include "perf/perf_controls.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace facesr {

void jaw_rigid_transform(const float* j, const Vec3& pivot, Mat3& R, Vec3& t) {
  const Vec3 r = Vec3(j[0], j[1], j[2]) * (M_PI / 180.0);
  const double angle = r.norm();
  // Below ~1e-12 rad the axis is noise and the rotation is the identity to
  // double precision anyway.
  R = angle > 1e-12 ? Mat3(Eigen::AngleAxisd(angle, r / angle)) : Mat3::Identity();
  t = pivot - R * pivot + Vec3(j[3], j[4], j[5]);
}

void frame_controls(const Performance& p, int frame, const Jaw& jaw, Controls& c) {
  require(frame >= 0 && frame < p.frames(), "performance '" + p.name + "': frame " + std::to_string(frame) +
                                                " is outside [0, " + std::to_string(p.frames()) + ")");
  const float* row = p.frame(frame);
  c.weights.assign(row, row + p.names.size());
  c.jaw_override = p.has_jaw;
  if (!p.has_jaw) {
    c.jaw_R = Mat3::Identity();
    c.jaw_t = Vec3::Zero();
    return;
  }
  require(p.jaw.size() == size_t(p.frames()) * 6, "performance '" + p.name + "': has " +
                                                      std::to_string(p.jaw.size()) + " jaw values for " +
                                                      std::to_string(p.frames()) + " frames (need 6 per frame)");
  jaw_rigid_transform(p.jaw_frame(frame), jaw.pivot, c.jaw_R, c.jaw_t);
}

}  // namespace facesr
