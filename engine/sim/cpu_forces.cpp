#include "sim/cpu_forces.h"

#include <cmath>

namespace facesr {

namespace {

void gather_corners(const double* x, const int32_t* nodes, double* xc) {
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) xc[3 * k + c] = x[3 * nodes[k] + c];
}

// Sums slot values (slot × 3) into nodes (node × 3); race-free by construction.
void gather_slots(const SimModel& m, const std::vector<double>& slots, std::vector<double>& out) {
  out.assign(3 * size_t(m.num_nodes), 0.0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < m.num_nodes; ++v) {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int i = m.inc_all.offset[v]; i < m.inc_all.offset[v + 1]; ++i) {
      const size_t s = size_t(m.inc_all.slot[i]);
      s0 += slots[3 * s];
      s1 += slots[3 * s + 1];
      s2 += slots[3 * s + 2];
    }
    out[3 * v] = s0;
    out[3 * v + 1] = s1;
    out[3 * v + 2] = s2;
  }
}

// Slot buffers reused across calls (one set per calling thread). On the HR
// mesh they are 20-60 MB, and allocating and zeroing them on every call took
// about 15 % of an HR frame (perf). Every slot is written before it is read.
std::vector<double>& slot_scratch(int which, size_t n) {
  thread_local std::vector<double> buffers[3];
  std::vector<double>& b = buffers[which];
  if (b.size() < n) b.resize(n);
  return b;
}

// Embedded surface point of vertex v.
Vec3 surface_point(const SimModel& m, const std::vector<double>& x, int v) {
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    const int n = m.surf_nodes[4 * v + k];
    p += m.surf_weights[4 * v + k] * Vec3(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
  }
  return p;
}

// Energy, gradient and Hessian of the external terms at one surface point.
double surface_terms(const SimModel& m, const FrameInputs& in, int v, const Vec3& p, Vec3* grad, Mat3* hess,
                     bool fix) {
  double e = 0;
  Vec3 g = Vec3::Zero();
  Mat3 H = Mat3::Zero();
  const double kt = m.track_k[v], ks = in.spring_k[v];
  if (kt > 0) {
    const Vec3 d = p - Vec3(in.target[3 * v], in.target[3 * v + 1], in.target[3 * v + 2]);
    e += 0.5 * kt * d.squaredNorm();
    g += kt * d;
    H.diagonal().array() += kt;
  }
  if (ks > 0) {
    const Vec3 d = p - Vec3(in.spring_target[3 * v], in.spring_target[3 * v + 1], in.spring_target[3 * v + 2]);
    e += 0.5 * ks * d.squaredNorm();
    g += ks * d;
    H.diagonal().array() += ks;
  }
  for (const auto& s : in.spheres) {
    const Vec3 r = p - s.centre;
    const double d = r.norm();
    if (d >= s.radius || d < 1e-12) continue;
    const Vec3 n = r / d;
    const double depth = s.radius - d;
    e += 0.5 * s.stiffness * depth * depth;
    g -= s.stiffness * depth * n;
    H += s.stiffness * n * n.transpose();
    // The curvature term is negative; the definiteness fix drops it.
    if (!fix) H -= s.stiffness * depth / d * (Mat3::Identity() - n * n.transpose());
  }
  if (grad) *grad = g;
  if (hess) *hess = H;
  return e;
}

}  // namespace

std::vector<double> tet_activations(const SimModel& m, const FrameInputs& in) {
  std::vector<double> a(m.num_tets, 0.0);
  for (int t = 0; t < m.num_tets; ++t)
    if (m.muscle[t] >= 0 && m.muscle[t] < int(in.muscle_activation.size())) a[t] = in.muscle_activation[m.muscle[t]];
  return a;
}

double total_energy(const SimModel& m, const FrameInputs& in, const std::vector<double>& alpha,
                    const std::vector<double>& x) {
  const fsr_material mat = m.material.to_c();
  double e = 0;
#pragma omp parallel for reduction(+ : e) schedule(static)
  for (int t = 0; t < m.num_tets; ++t) {
    double xc[12], F[9];
    gather_corners(x.data(), &m.tets[4 * t], xc);
    fsr_tet_F(xc, &m.Dminv[9 * t], F);
    e += m.volume[t] * fsr_energy_density(&mat, F, &m.fibre[3 * t], m.phi[t], alpha[t]);
  }
  double es = 0;
#pragma omp parallel for reduction(+ : es) schedule(static)
  for (int v = 0; v < m.num_surface; ++v) es += surface_terms(m, in, v, surface_point(m, x, v), nullptr, nullptr, true);
  return e + es;
}

void energy_gradient(const SimModel& m, const FrameInputs& in, const std::vector<double>& alpha,
                     const std::vector<double>& x, std::vector<double>& g) {
  const fsr_material mat = m.material.to_c();
  std::vector<double>& slots = slot_scratch(0, 3 * 4 * size_t(m.num_tets + m.num_surface));
#pragma omp parallel for schedule(static)
  for (int t = 0; t < m.num_tets; ++t) {
    double xc[12], F[9], P[9];
    gather_corners(x.data(), &m.tets[4 * t], xc);
    fsr_tet_F(xc, &m.Dminv[9 * t], F);
    fsr_stress(&mat, F, &m.fibre[3 * t], m.phi[t], alpha[t], P);
    fsr_tet_scatter(P, &m.Dminv[9 * t], m.volume[t], &slots[12 * size_t(t)]);
  }
#pragma omp parallel for schedule(static)
  for (int v = 0; v < m.num_surface; ++v) {
    Vec3 gp;
    surface_terms(m, in, v, surface_point(m, x, v), &gp, nullptr, true);
    double* s = &slots[12 * (size_t(m.num_tets) + v)];
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) s[3 * k + c] = m.surf_weights[4 * v + k] * gp[c];
  }
  gather_slots(m, slots, g);
}

void element_hessian(const SimModel& m, const FrameInputs& in, const std::vector<double>& alpha,
                     const std::vector<double>& x, bool fix, ElementHessian& H) {
  const fsr_material mat = m.material.to_c();
  H.C.resize(81 * size_t(m.num_tets));
  H.surf.resize(9 * size_t(m.num_surface));
  std::vector<double>& dslots = slot_scratch(1, 9 * 4 * size_t(m.num_tets + m.num_surface));
#pragma omp parallel for schedule(static)
  for (int t = 0; t < m.num_tets; ++t) {
    double xc[12], F[9];
    gather_corners(x.data(), &m.tets[4 * t], xc);
    fsr_tet_F(xc, &m.Dminv[9 * t], F);
    double* C = &H.C[81 * size_t(t)];
    fsr_stress_derivative(&mat, F, &m.fibre[3 * t], m.phi[t], alpha[t], fix ? 1 : 0, C);
    fsr_tet_diag_blocks(C, &m.Dminv[9 * t], m.volume[t], &dslots[36 * size_t(t)]);
  }
#pragma omp parallel for schedule(static)
  for (int v = 0; v < m.num_surface; ++v) {
    Mat3 Hp;
    surface_terms(m, in, v, surface_point(m, x, v), nullptr, &Hp, fix);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) H.surf[9 * size_t(v) + 3 * i + j] = Hp(i, j);
    double* d = &dslots[36 * (size_t(m.num_tets) + v)];
    for (int k = 0; k < 4; ++k) {
      const double w2 = m.surf_weights[4 * v + k] * m.surf_weights[4 * v + k];
      for (int e = 0; e < 9; ++e) d[9 * k + e] = w2 * H.surf[9 * size_t(v) + e];
    }
  }
  H.diag.assign(9 * size_t(m.num_nodes), 0.0);
#pragma omp parallel for schedule(static)
  for (int v = 0; v < m.num_nodes; ++v)
    for (int i = m.inc_all.offset[v]; i < m.inc_all.offset[v + 1]; ++i)
      for (int e = 0; e < 9; ++e) H.diag[9 * size_t(v) + e] += dslots[9 * size_t(m.inc_all.slot[i]) + e];
}

void hessian_product(const SimModel& m, const ElementHessian& H, const std::vector<double>& dx,
                     std::vector<double>& y) {
  std::vector<double>& slots = slot_scratch(2, 3 * 4 * size_t(m.num_tets + m.num_surface));
#pragma omp parallel for schedule(static)
  for (int t = 0; t < m.num_tets; ++t) {
    double xc[12];
    gather_corners(dx.data(), &m.tets[4 * t], xc);
    fsr_tet_stiffness_product(&H.C[81 * size_t(t)], &m.Dminv[9 * t], m.volume[t], xc, &slots[12 * size_t(t)]);
  }
#pragma omp parallel for schedule(static)
  for (int v = 0; v < m.num_surface; ++v) {
    const double* Hs = &H.surf[9 * size_t(v)];
    double* s = &slots[12 * (size_t(m.num_tets) + v)];
    double q[3] = {0, 0, 0};
    for (int k = 0; k < 4; ++k) {
      const int n = m.surf_nodes[4 * v + k];
      for (int c = 0; c < 3; ++c) q[c] += m.surf_weights[4 * v + k] * dx[3 * size_t(n) + c];
    }
    double hq[3];
    for (int i = 0; i < 3; ++i) hq[i] = Hs[3 * i] * q[0] + Hs[3 * i + 1] * q[1] + Hs[3 * i + 2] * q[2];
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) s[3 * k + c] = m.surf_weights[4 * v + k] * hq[c];
  }
  gather_slots(m, slots, y);
}

int count_inverted(const SimModel& m, const std::vector<double>& x) {
  int n = 0;
#pragma omp parallel for reduction(+ : n) schedule(static)
  for (int t = 0; t < m.num_tets; ++t) {
    double xc[12], F[9];
    gather_corners(x.data(), &m.tets[4 * t], xc);
    fsr_tet_F(xc, &m.Dminv[9 * t], F);
    n += fsr_det3(F) <= 0;
  }
  return n;
}

}  // namespace facesr
