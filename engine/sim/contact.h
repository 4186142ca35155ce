#pragma once
// Contacts enter the quasistatic solve as one-sided penalty planes on mesh
// nodes: a node p in contact with an obstacle surface at point q with outward
// normal n has energy ½·k·max(0, (q − p)·n)². The planes are found anew at the
// start of every Newton iteration (by a ContactSource, e.g. the Embree mouth
// collider in engine/collide) and held fixed during that iteration's linear
// solve and line search, so each iteration minimises a smooth convex penalty
// (the usual "contact springs" linearisation of the non-penetration constraint).
#include <vector>

#include "core/types.h"
#include "sim/controls.h"

namespace facesr {

struct ContactPlane {
  int node = -1;
  Vec3 point = Vec3::Zero();   // closest point on the obstacle (cm)
  Vec3 normal = Vec3::Zero();  // unit outward normal of the obstacle at `point`
  double stiffness = 0;        // kPa·cm (force per cm of penetration)
  int kind = 0;                // what the obstacle is (source-specific, for reports)
  // How far the node was behind the obstacle where it was detected (cm);
  // negative: a gap within the detection margin (the plane is kept so that the
  // contact set does not flicker between Newton iterations).
  double penetration = 0;
};

// Penetration depth of the node behind the plane (cm, ≥ 0).
inline double contact_depth(const ContactPlane& c, const std::vector<double>& x) {
  const Vec3 p(x[3 * size_t(c.node)], x[3 * size_t(c.node) + 1], x[3 * size_t(c.node) + 2]);
  const double d = (c.point - p).dot(c.normal);
  return d > 0 ? d : 0;
}

class ContactSource {
 public:
  virtual ~ContactSource() = default;
  // Finds the penetrating nodes at positions x (node × 3, cm) under this
  // frame's bone motion; at most one plane per node.
  virtual void detect(const std::vector<double>& x, const FrameInputs& in, std::vector<ContactPlane>& out) = 0;
};

// Penalty energy, gradient (added into g), Hessian diagonal blocks (added into
// diag, node × 9) and Hessian product (added into y) of the contact planes.
double contact_energy(const std::vector<ContactPlane>& c, const std::vector<double>& x);
void contact_gradient(const std::vector<ContactPlane>& c, const std::vector<double>& x, std::vector<double>& g);
void contact_hessian_diag(const std::vector<ContactPlane>& c, const std::vector<double>& x,
                          std::vector<double>& diag);
void contact_product(const std::vector<ContactPlane>& c, const std::vector<double>& x,
                     const std::vector<double>& dx, std::vector<double>& y);
// Largest ContactPlane::penetration (0 when none is positive) and the number
// of planes with positive penetration.
double max_penetration(const std::vector<ContactPlane>& c);
int count_penetrating(const std::vector<ContactPlane>& c);

}  // namespace facesr
