#include "sim/contact.h"

#include <algorithm>

namespace facesr {

// Planes hold at most one entry per node, so the loops below write each node
// once and need no synchronisation; contact sets are small (hundreds), so they
// run serially.

double contact_energy(const std::vector<ContactPlane>& c, const std::vector<double>& x) {
  double e = 0;
  for (const auto& p : c) {
    const double d = contact_depth(p, x);
    e += 0.5 * p.stiffness * d * d;
  }
  return e;
}

void contact_gradient(const std::vector<ContactPlane>& c, const std::vector<double>& x, std::vector<double>& g) {
  for (const auto& p : c) {
    const double d = contact_depth(p, x);
    if (d <= 0) continue;
    // E = ½k((q − x)·n)² → ∂E/∂x = −k d n.
    for (int k = 0; k < 3; ++k) g[3 * size_t(p.node) + k] -= p.stiffness * d * p.normal[k];
  }
}

void contact_hessian_diag(const std::vector<ContactPlane>& c, const std::vector<double>& x,
                          std::vector<double>& diag) {
  for (const auto& p : c) {
    if (contact_depth(p, x) <= 0) continue;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) diag[9 * size_t(p.node) + 3 * i + j] += p.stiffness * p.normal[i] * p.normal[j];
  }
}

void contact_product(const std::vector<ContactPlane>& c, const std::vector<double>& x,
                     const std::vector<double>& dx, std::vector<double>& y) {
  for (const auto& p : c) {
    if (contact_depth(p, x) <= 0) continue;
    const size_t o = 3 * size_t(p.node);
    const double nd = p.normal[0] * dx[o] + p.normal[1] * dx[o + 1] + p.normal[2] * dx[o + 2];
    for (int k = 0; k < 3; ++k) y[o + k] += p.stiffness * nd * p.normal[k];
  }
}

double max_penetration(const std::vector<ContactPlane>& c) {
  double m = 0;
  for (const auto& p : c) m = std::max(m, p.penetration);
  return m;
}

int count_penetrating(const std::vector<ContactPlane>& c) {
  int n = 0;
  for (const auto& p : c) n += p.penetration > 0;
  return n;
}

}  // namespace facesr
