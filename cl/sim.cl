// Quasistatic Newton/PCG solver kernels for the LR (or HR) tet mesh. Compiled
// after fsr_material.h, which supplies fsr_real and the material functions.
//
// Scatter/gather: every tet corner and every embedded surface-vertex corner
// owns one "slot" (tet t corner k: 4t+k; surface vertex v corner k:
// 4T+4v+k). Element kernels write their slots, then `gather_nodes` sums each
// node's slots through a CSR incidence list: no atomics, deterministic sums.
//
// Frame buffer layout (fsr_real): jaw R (9, row-major), jaw t (3), then per
// sphere collider centre (3), radius, stiffness.

#define SLOT3(buf, s) ((buf) + 3 * (size_t)(s))

__kernel void frame_tet_alpha(const uint T, __global const int* muscle, __global const fsr_real* act,
                              __global fsr_real* alpha) {
  const uint t = get_global_id(0);
  if (t >= T) return;
  const int m = muscle[t];
  alpha[t] = m >= 0 ? act[m] : 0;
}

// Track targets: rest embedding plus the linear blendshape offsets.
fsr_real target_value(const uint i, const uint n, const uint B, __global const fsr_real* surf_rest,
                      __global const float* deltas, __global const float* weights) {
  fsr_real v = surf_rest[i];
  for (uint b = 0; b < B; ++b) {
    const float w = weights[b];
    if (w != 0.0f) v += (fsr_real)w * (fsr_real)deltas[(size_t)b * n + i];
  }
  return v;
}

__kernel void frame_targets(const uint S, const uint B, __global const fsr_real* surf_rest,
                            __global const float* deltas, __global const float* weights,
                            __global fsr_real* target) {
  const uint i = get_global_id(0);
  if (i < 3 * S) target[i] = target_value(i, 3 * S, B, surf_rest, deltas, weights);
}

// Bone nodes to their prescribed positions: cranium at rest, jaw moved rigidly.
__kernel void apply_dirichlet(const uint N, __global const fsr_real* rest, __global const uchar* bone,
                              __global const fsr_real* frame, __global fsr_real* x) {
  const uint v = get_global_id(0);
  if (v >= N || bone[v] == 0) return;
  const fsr_real X0 = rest[3 * v], X1 = rest[3 * v + 1], X2 = rest[3 * v + 2];
  if (bone[v] == 1) {
    x[3 * v] = X0;
    x[3 * v + 1] = X1;
    x[3 * v + 2] = X2;
  } else {
    for (int i = 0; i < 3; ++i)
      x[3 * v + i] = frame[3 * i] * X0 + frame[3 * i + 1] * X1 + frame[3 * i + 2] * X2 + frame[9 + i];
  }
}

void load_tet(uint t, __global const int* tets, __global const fsr_real* x, __global const fsr_real* Dminv_g,
              __global const fsr_real* fibre_g, fsr_real* xc, fsr_real* Dminv, fsr_real* a) {
  for (int k = 0; k < 4; ++k) {
    const int n = tets[4 * t + k];
    for (int c = 0; c < 3; ++c) xc[3 * k + c] = x[3 * n + c];
  }
  for (int k = 0; k < 9; ++k) Dminv[k] = Dminv_g[9 * (size_t)t + k];
  for (int k = 0; k < 3; ++k) a[k] = fibre_g[3 * t + k];
}

fsr_material material_of(__global const fsr_real* mp) {
  fsr_material m;
  m.mu10 = mp[0];
  m.mu01 = mp[1];
  m.kappa = mp[2];
  m.j_min = mp[3];
  m.sigma_max = mp[4];
  m.p1 = mp[5];
  m.p2 = mp[6];
  m.stretch_lin = mp[7];
  return m;
}

__kernel void tet_energy(const uint T, __global const fsr_real* mp, __global const int* tets,
                         __global const fsr_real* x, __global const fsr_real* Dminv_g, __global const fsr_real* vol,
                         __global const fsr_real* fibre_g, __global const fsr_real* phi,
                         __global const fsr_real* alpha, __global fsr_real* e) {
  const uint t = get_global_id(0);
  if (t >= T) return;
  const fsr_material m = material_of(mp);
  fsr_real xc[12], Dminv[9], a[3], F[9];
  load_tet(t, tets, x, Dminv_g, fibre_g, xc, Dminv, a);
  fsr_tet_F(xc, Dminv, F);
  e[t] = vol[t] * fsr_energy_density(&m, F, a, phi[t], alpha[t]);
}

__kernel void tet_gradient(const uint T, __global const fsr_real* mp, __global const int* tets,
                           __global const fsr_real* x, __global const fsr_real* Dminv_g, __global const fsr_real* vol,
                           __global const fsr_real* fibre_g, __global const fsr_real* phi,
                           __global const fsr_real* alpha, __global fsr_real* slots) {
  const uint t = get_global_id(0);
  if (t >= T) return;
  const fsr_material m = material_of(mp);
  fsr_real xc[12], Dminv[9], a[3], F[9], P[9], g[12];
  load_tet(t, tets, x, Dminv_g, fibre_g, xc, Dminv, a);
  fsr_tet_F(xc, Dminv, F);
  fsr_stress(&m, F, a, phi[t], alpha[t], P);
  fsr_tet_scatter(P, Dminv, vol[t], g);
  for (int k = 0; k < 12; ++k) slots[12 * (size_t)t + k] = g[k];
}

// Tets per vector for the element kernels below: one 512-bit register,
// 8 doubles or 16 floats (the host's kProductLanes). preal holds one value
// per tet, pint one index per tet; pstore_float stores a preal as floats.
#ifdef FSR_REAL_FLOAT
#define PRODUCT_LANES 16
typedef float16 preal;
typedef int16 pmask;
typedef int16 pint;
#define pload(ptr) vload16(0, ptr)
#define pstore(v, ptr) vstore16((v), 0, (ptr))
#define iload(ptr) vload16(0, ptr)
#define CLOAD(ptr) vload16(0, ptr)
#define pstore_float(v, ptr) vstore16((v), 0, (ptr))
#else
#define PRODUCT_LANES 8
typedef double8 preal;
typedef long8 pmask;
typedef int8 pint;
#define pload(ptr) vload8(0, ptr)
#define pstore(v, ptr) vstore8((v), 0, (ptr))
#define iload(ptr) vload8(0, ptr)
#define CLOAD(ptr) convert_double8(vload8(0, ptr))
#define pstore_float(v, ptr) vstore8(convert_float8(v), 0, (ptr))
#endif

// The tets' stiffness blocks (tet_blocks) in groups of PRODUCT_LANES tets:
// value k of tet t at KE_INDEX(t, k), so that the vector kernel stores each
// value as one vector and a block's nine values lie close together for the
// gather in assemble_stiffness (k·Tp strides put each in another cache line).
#define KE_INDEX(t, k) \
  ((((size_t)(t) / PRODUCT_LANES) * 90 + (size_t)(k)) * PRODUCT_LANES + ((t) % PRODUCT_LANES))

// dP/dF (definiteness-fixed) per tet, packed and component-major (C_g[k·Tp +
// t], Tp the tet count rounded up to PRODUCT_LANES), and its four diagonal
// 3x3 blocks (in full precision, for the preconditioner); or, with
// `assemble`, the tet's ten stiffness blocks instead (Ke, see KE_INDEX),
// which assemble_stiffness sums into K.
__kernel void tet_hessian(const uint T, __global const fsr_real* mp, __global const int* tets,
                          __global const fsr_real* x, __global const fsr_real* Dminv_g, __global const fsr_real* vol,
                          __global const fsr_real* fibre_g, __global const fsr_real* phi,
                          __global const fsr_real* alpha, const int fix, const uint Tp, __global float* C_g,
                          __global fsr_real* dslots, const int assemble, __global float* Ke) {
  const uint t = get_global_id(0);
  if (t >= T) return;
  const fsr_material m = material_of(mp);
  fsr_real xc[12], Dminv[9], a[3], F[9], C[81], D[36];
  load_tet(t, tets, x, Dminv_g, fibre_g, xc, Dminv, a);
  fsr_tet_F(xc, Dminv, F);
  fsr_stress_derivative(&m, F, a, phi[t], alpha[t], fix, C);
  if (assemble) {
    fsr_real Kb[90];
    fsr_tet_blocks(C, Dminv, vol[t], Kb);
    for (int k = 0; k < 90; ++k) Ke[KE_INDEX(t, k)] = (float)Kb[k];
    return;
  }
  fsr_tet_diag_blocks(C, Dminv, vol[t], D);
  // dP/dF is symmetric (the energy's Hessian in F): its upper triangle, in
  // float, is what product_tets reads (see there).
  int n = 0;
  for (int r = 0; r < 9; ++r)
    for (int c = r; c < 9; ++c) C_g[(size_t)(n++) * Tp + t] = (float)(0.5 * (C[9 * r + c] + C[9 * c + r]));
  for (int k = 0; k < 36; ++k) dslots[36 * (size_t)t + k] = D[k];
}

// ---- Element kernels, a vector of tets per work-item (CPU devices) ----
// PoCL compiles a one-tet-per-work-item kernel with loops as scalar code, so
// on CPU devices every per-tet kernel (energy, gradient, Hessian, stiffness
// product) takes PRODUCT_LANES consecutive tets, one per vector lane: the
// material body (cl/fsr_material_body.h) instantiated for vectors. Per-tet
// data are component-major (x[k·Tp + t], Tp = T rounded up to whole
// vectors); padding tets (t ≥ T) have zero Dminv, volume, fibre fraction and
// activation, stay finite, and are never stored into slots. The one-tet
// kernels above stay for GPUs, where a work-item per tet is the natural fit.

#define FSR_T preal
#define FSR(name) fsr8_##name
#define FSR_IF(c, a, b) select((b), (a), (c))
#define FSR_ALL(c) all(c)
#define FSR_M pmask
#include "fsr_material_body.h"
#undef FSR_T
#undef FSR
#undef FSR_IF
#undef FSR_ALL
#undef FSR_M

// The 4 corners' node vectors (x: node × 3) of tets t0… (one vector), corner-major
// per lane: xc[3k + c] is component c of corner k.
void gather_corners8(uint t0, uint Tp, __global const int* tets_cm, __global const fsr_real* x, preal* xc) {
  #pragma unroll
  for (int k = 0; k < 4; ++k) {
    const pint n = 3 * iload(tets_cm + (size_t)k * Tp + t0);
    #pragma unroll
    for (int c = 0; c < 3; ++c)
#if PRODUCT_LANES == 16
      xc[3 * k + c] = (preal)(x[n.s0 + c], x[n.s1 + c], x[n.s2 + c], x[n.s3 + c], x[n.s4 + c], x[n.s5 + c],
                              x[n.s6 + c], x[n.s7 + c], x[n.s8 + c], x[n.s9 + c], x[n.sa + c], x[n.sb + c],
                              x[n.sc + c], x[n.sd + c], x[n.se + c], x[n.sf + c]);
#else
      xc[3 * k + c] = (preal)(x[n.s0 + c], x[n.s1 + c], x[n.s2 + c], x[n.s3 + c], x[n.s4 + c], x[n.s5 + c],
                              x[n.s6 + c], x[n.s7 + c]);
#endif
  }
}

void load_tets8(uint t0, uint Tp, __global const int* tets_cm, __global const fsr_real* x,
                __global const fsr_real* Dminv_cm, __global const fsr_real* fibre_cm, preal* xc, preal* Dm,
                preal* a) {
  gather_corners8(t0, Tp, tets_cm, x, xc);
  #pragma unroll
  for (int k = 0; k < 9; ++k) Dm[k] = pload(Dminv_cm + (size_t)k * Tp + t0);
  #pragma unroll
  for (int k = 0; k < 3; ++k) a[k] = pload(fibre_cm + (size_t)k * Tp + t0);
}

// Stores `count` per-tet vectors v[k] tet-major (out[count·t + k]) for the real tets.
void store_tets8(uint T, uint t0, int count, const preal* v, __global fsr_real* out) {
  fsr_real lane[PRODUCT_LANES];
  const uint n = min((uint)PRODUCT_LANES, T - t0);
  for (int k = 0; k < count; ++k) {
    pstore(v[k], lane);
    for (uint l = 0; l < n; ++l) out[count * (size_t)(t0 + l) + k] = lane[l];
  }
}

// e has Tp entries (padding tets get 0).
__kernel void tet_energy8(const uint T, const uint Tp, __global const fsr_real* mp, __global const int* tets_cm,
                          __global const fsr_real* x, __global const fsr_real* Dminv_cm,
                          __global const fsr_real* vol_p, __global const fsr_real* fibre_cm,
                          __global const fsr_real* phi_p, __global const fsr_real* alpha_p, __global fsr_real* e) {
  const uint t0 = get_global_id(0) * PRODUCT_LANES;
  if (t0 >= T) return;
  const fsr_material m = material_of(mp);
  preal xc[12], Dm[9], a[3], F[9];
  load_tets8(t0, Tp, tets_cm, x, Dminv_cm, fibre_cm, xc, Dm, a);
  fsr8_tet_F(xc, Dm, F);
  const preal psi = fsr8_energy_density(&m, F, a, pload(phi_p + t0), pload(alpha_p + t0));
  pstore(pload(vol_p + t0) * psi, e + t0);
}

__kernel void tet_gradient8(const uint T, const uint Tp, __global const fsr_real* mp, __global const int* tets_cm,
                            __global const fsr_real* x, __global const fsr_real* Dminv_cm,
                            __global const fsr_real* vol_p, __global const fsr_real* fibre_cm,
                            __global const fsr_real* phi_p, __global const fsr_real* alpha_p,
                            __global fsr_real* slots) {
  const uint t0 = get_global_id(0) * PRODUCT_LANES;
  if (t0 >= T) return;
  const fsr_material m = material_of(mp);
  preal xc[12], Dm[9], a[3], F[9], P[9], g[12];
  load_tets8(t0, Tp, tets_cm, x, Dminv_cm, fibre_cm, xc, Dm, a);
  fsr8_tet_F(xc, Dm, F);
  fsr8_stress(&m, F, a, pload(phi_p + t0), pload(alpha_p + t0), P);
  fsr8_tet_scatter(P, Dm, pload(vol_p + t0), g);
  store_tets8(T, t0, 12, g, slots);
}

// As tet_hessian: packed float dP/dF for product_tets and full-precision
// diagonal blocks, or with `assemble` the ten stiffness blocks.
__kernel void tet_hessian8(const uint T, const uint Tp, __global const fsr_real* mp, __global const int* tets_cm,
                           __global const fsr_real* x, __global const fsr_real* Dminv_cm,
                           __global const fsr_real* vol_p, __global const fsr_real* fibre_cm,
                           __global const fsr_real* phi_p, __global const fsr_real* alpha_p, const int fix,
                           __global float* C_g, __global fsr_real* dslots, const int assemble,
                           __global float* Ke) {
  const uint t0 = get_global_id(0) * PRODUCT_LANES;
  if (t0 >= T) return;
  const fsr_material m = material_of(mp);
  preal xc[12], Dm[9], a[3], F[9], C[81], D[36];
  load_tets8(t0, Tp, tets_cm, x, Dminv_cm, fibre_cm, xc, Dm, a);
  fsr8_tet_F(xc, Dm, F);
  fsr8_stress_derivative(&m, F, a, pload(phi_p + t0), pload(alpha_p + t0), fix, C);
  if (assemble) {  // padding tets have zero volume, so zero blocks
    preal Kb[90];
    fsr8_tet_blocks(C, Dm, pload(vol_p + t0), Kb);
    #pragma unroll
    for (int k = 0; k < 90; ++k) pstore_float(Kb[k], Ke + KE_INDEX(t0, k));
    return;
  }
  fsr8_tet_diag_blocks(C, Dm, pload(vol_p + t0), D);
  int n = 0;
  #pragma unroll
  for (int r = 0; r < 9; ++r)
    #pragma unroll
    for (int c = r; c < 9; ++c)
      pstore_float((fsr_real)0.5 * (C[9 * r + c] + C[9 * c + r]), C_g + (size_t)(n++) * Tp + t0);
  store_tets8(T, t0, 36, D, dslots);
}

// frame_targets for CPU devices: 8 consecutive values per work-item, each
// shape's deltas read as one 8-wide load (the one-value kernel's loop over
// shapes is scalar code on PoCL). Same sum, same order.
__kernel void frame_targets8(const uint S, const uint B, __global const fsr_real* surf_rest,
                             __global const float* deltas, __global const float* weights,
                             __global fsr_real* target) {
  const uint i0 = get_global_id(0) * 8, n = 3 * S;
  if (i0 >= n) return;
  if (i0 + 8 > n) {  // the tail, one value at a time
    for (uint i = i0; i < n; ++i) target[i] = target_value(i, n, B, surf_rest, deltas, weights);
    return;
  }
#ifdef FSR_REAL_FLOAT
#define TO_REAL8(x) (x)
  float8 v = vload8(0, surf_rest + i0);
#else
#define TO_REAL8(x) convert_double8(x)
  double8 v = vload8(0, surf_rest + i0);
#endif
  for (uint b = 0; b < B; ++b) {
    const float w = weights[b];
    if (w != 0.0f) v += (fsr_real)w * TO_REAL8(vload8(0, deltas + (size_t)b * n + i0));
  }
#undef TO_REAL8
  vstore8(v, 0, target + i0);
}

// External terms at one embedded surface point: track spring, point spring,
// sphere penalties. mode 0: energy → e[v]; 1: gradient → slots; 2: Hessian
// with the definiteness fix (the spheres' negative curvature term dropped),
// 3: exact Hessian → surfH and dslots.
void surface_point(uint v, __global const int* sn, __global const fsr_real* sw, __global const fsr_real* x,
                   fsr_real* p, fsr_real* w) {
  p[0] = p[1] = p[2] = 0;
  for (int k = 0; k < 4; ++k) {
    const int n = sn[4 * v + k];
    w[k] = sw[4 * v + k];
    for (int c = 0; c < 3; ++c) p[c] += w[k] * x[3 * n + c];
  }
}

// Work-item i handles surface vertex slist[i]; its slots are 4T + 4i + k.
__kernel void surface_terms(const uint S, const uint T, const int mode, __global const int* slist,
                            __global const int* sn,
                            __global const fsr_real* sw, __global const fsr_real* x, __global const fsr_real* track_k,
                            __global const fsr_real* target, __global const fsr_real* spring_k,
                            __global const fsr_real* spring_target, __global const fsr_real* frame,
                            const uint nspheres, __global fsr_real* e, __global fsr_real* slots,
                            __global fsr_real* surfH, __global fsr_real* dslots) {
  const uint i = get_global_id(0);
  if (i >= S) return;
  const int v = slist[i];
  fsr_real p[3], w[4], g[3] = {0, 0, 0}, H[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, en = 0;
  surface_point(v, sn, sw, x, p, w);
  const fsr_real kt = track_k[v], ks = spring_k[v];
  if (kt > 0) {
    fsr_real d2 = 0;
    for (int c = 0; c < 3; ++c) {
      const fsr_real d = p[c] - target[3 * v + c];
      g[c] += kt * d;
      d2 += d * d;
      H[4 * c] += kt;
    }
    en += (fsr_real)0.5 * kt * d2;
  }
  if (ks > 0) {
    fsr_real d2 = 0;
    for (int c = 0; c < 3; ++c) {
      const fsr_real d = p[c] - spring_target[3 * v + c];
      g[c] += ks * d;
      d2 += d * d;
      H[4 * c] += ks;
    }
    en += (fsr_real)0.5 * ks * d2;
  }
  for (uint s = 0; s < nspheres; ++s) {
    __global const fsr_real* sp = frame + 12 + 5 * s;
    const fsr_real r[3] = {p[0] - sp[0], p[1] - sp[1], p[2] - sp[2]};
    const fsr_real d = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (d >= sp[3] || d < (fsr_real)1e-12) continue;
    const fsr_real depth = sp[3] - d, k = sp[4];
    en += (fsr_real)0.5 * k * depth * depth;
    for (int c = 0; c < 3; ++c) {
      g[c] -= k * depth * r[c] / d;
      for (int q = 0; q < 3; ++q) {
        const fsr_real nn = r[c] * r[q] / (d * d);
        H[3 * c + q] += k * nn;
        if (mode == 3) H[3 * c + q] -= k * depth / d * ((c == q ? 1 : 0) - nn);
      }
    }
  }
  if (mode == 0) {
    e[i] = en;
  } else if (mode == 1) {
    __global fsr_real* out = slots + 12 * ((size_t)T + i);
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) out[3 * k + c] = w[k] * g[c];
  } else {
    for (int k = 0; k < 9; ++k) surfH[9 * (size_t)i + k] = H[k];
    __global fsr_real* out = dslots + 36 * ((size_t)T + i);
    for (int k = 0; k < 4; ++k)
      for (int q = 0; q < 9; ++q) out[9 * k + q] = w[k] * w[k] * H[q];
  }
}

// out[node] = Σ slots of the node; bone nodes get 0 (they are not unknowns).
__kernel void gather_nodes(const uint N, __global const int* inc_offset, __global const int* inc_slot,
                           __global const uchar* bone, __global const fsr_real* slots, __global fsr_real* out) {
  const uint v = get_global_id(0);
  if (v >= N) return;
  fsr_real s0 = 0, s1 = 0, s2 = 0;
  if (bone[v] == 0) {
    for (int i = inc_offset[v]; i < inc_offset[v + 1]; ++i) {
      __global const fsr_real* s = SLOT3(slots, inc_slot[i]);
      s0 += s[0];
      s1 += s[1];
      s2 += s[2];
    }
  }
  out[3 * v] = s0;
  out[3 * v + 1] = s1;
  out[3 * v + 2] = s2;
}

// inv = A⁻¹ for a 3x3 block, left as it is (zero) when A is singular.
void inverse3_or_zero(const fsr_real* A, fsr_real* inv) {
  const fsr_real det = fsr_det3(A);
  if (!(fabs(det) > (fsr_real)1e-30)) return;
  inv[0] = (A[4] * A[8] - A[5] * A[7]) / det;
  inv[1] = (A[2] * A[7] - A[1] * A[8]) / det;
  inv[2] = (A[1] * A[5] - A[2] * A[4]) / det;
  inv[3] = (A[5] * A[6] - A[3] * A[8]) / det;
  inv[4] = (A[0] * A[8] - A[2] * A[6]) / det;
  inv[5] = (A[2] * A[3] - A[0] * A[5]) / det;
  inv[6] = (A[3] * A[7] - A[4] * A[6]) / det;
  inv[7] = (A[1] * A[6] - A[0] * A[7]) / det;
  inv[8] = (A[0] * A[4] - A[1] * A[3]) / det;
}

// Block-Jacobi preconditioner: inverse of each free node's 3x3 diagonal block.
__kernel void gather_diag_inverse(const uint N, __global const int* inc_offset, __global const int* inc_slot,
                                  __global const uchar* bone, __global const fsr_real* dslots,
                                  __global fsr_real* Minv) {
  const uint v = get_global_id(0);
  if (v >= N) return;
  fsr_real D[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (int i = inc_offset[v]; i < inc_offset[v + 1]; ++i)
    for (int k = 0; k < 9; ++k) D[k] += dslots[9 * (size_t)inc_slot[i] + k];
  fsr_real inv[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  if (bone[v] == 0) inverse3_or_zero(D, inv);
  for (int k = 0; k < 9; ++k) Minv[9 * (size_t)v + k] = inv[k];
}

// ---- CG vector operations (n = 3 × nodes) ----

// Work-group sums in local memory (power-of-two local size); every
// work-item of the group must call them. Element 0 holds the result.
void group_sum(__local fsr_real* s1) {
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
    if (get_local_id(0) < stride) s1[get_local_id(0)] += s1[get_local_id(0) + stride];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

void group_sum2(__local fsr_real* s1, __local fsr_real* s2) {
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint stride = get_local_size(0) / 2; stride > 0; stride /= 2) {
    const uint lid = get_local_id(0);
    if (lid < stride) {
      s1[lid] += s1[lid + stride];
      s2[lid] += s2[lid + stride];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}


__kernel void precondition(const uint N, __global const fsr_real* Minv, __global const fsr_real* r,
                           __global fsr_real* z) {
  const uint v = get_global_id(0);
  if (v >= N) return;
  __global const fsr_real* M = Minv + 9 * (size_t)v;
  const fsr_real r0 = r[3 * v], r1 = r[3 * v + 1], r2 = r[3 * v + 2];
  for (int i = 0; i < 3; ++i) z[3 * v + i] = M[3 * i] * r0 + M[3 * i + 1] * r1 + M[3 * i + 2] * r2;
}

// Work-group partial sums of a·b and c·d (the second pair may alias the first).
// Local size must be a power of two; the host adds the partials.
__kernel void dot2_partial(const uint n, __global const fsr_real* a, __global const fsr_real* b,
                           __global const fsr_real* c, __global const fsr_real* d, __global fsr_real* partial,
                           __local fsr_real* s1, __local fsr_real* s2) {
  const uint lid = get_local_id(0);
  fsr_real acc1 = 0, acc2 = 0;
  for (uint i = get_global_id(0); i < n; i += get_global_size(0)) {
    acc1 += a[i] * b[i];
    acc2 += c[i] * d[i];
  }
  s1[lid] = acc1;
  s2[lid] = acc2;
  group_sum2(s1, s2);
  if (lid == 0) {
    partial[2 * get_group_id(0)] = s1[0];
    partial[2 * get_group_id(0) + 1] = s2[0];
  }
}

__kernel void sum_partial(const uint n, __global const fsr_real* a, __global fsr_real* partial,
                          __local fsr_real* s1) {
  const uint lid = get_local_id(0);
  fsr_real acc = 0;
  for (uint i = get_global_id(0); i < n; i += get_global_size(0)) acc += a[i];
  s1[lid] = acc;
  group_sum(s1);
  if (lid == 0) partial[get_group_id(0)] = s1[0];
}

// p = z + β p

// y = a + s b
__kernel void axpy_to(const uint n, const fsr_real s, __global const fsr_real* a, __global const fsr_real* b,
                      __global fsr_real* y) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  y[i] = a[i] + s * b[i];
}

__kernel void tet_inverted(const uint T, __global const int* tets, __global const fsr_real* x,
                           __global const fsr_real* Dminv_g, __global fsr_real* flag) {
  const uint t = get_global_id(0);
  if (t >= T) return;
  fsr_real xc[12], Dminv[9], F[9];
  for (int k = 0; k < 4; ++k) {
    const int n = tets[4 * t + k];
    for (int c = 0; c < 3; ++c) xc[3 * k + c] = x[3 * n + c];
  }
  for (int k = 0; k < 9; ++k) Dminv[k] = Dminv_g[9 * (size_t)t + k];
  fsr_tet_F(xc, Dminv, F);
  flag[t] = fsr_det3(F) <= 0 ? 1 : 0;
}

__kernel void embed_surface(const uint S, __global const int* sn, __global const fsr_real* sw,
                            __global const fsr_real* x, __global float* out) {
  const uint v = get_global_id(0);
  if (v >= S) return;
  fsr_real p[3], w[4];
  surface_point(v, sn, sw, x, p, w);
  for (int c = 0; c < 3; ++c) out[3 * v + c] = (float)p[c];
}

// y = s a
__kernel void scale_to(const uint n, const fsr_real s, __global const fsr_real* a, __global fsr_real* y) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  y[i] = s * a[i];
}

// ---- Fused CG kernels: one launch where the unfused sequence needed three,
// because on CPU devices launch latency rivals the arithmetic. Work-item per
// node, power-of-two local size, one partial sum per work-group.

// The stiffness product K p, the CG's cost, in two launches: product_tets
// and product_surface. PoCL runs per-tet code as scalar code (a work-item
// body with loops is not vectorised across work-items), so product_tets is
// explicitly SIMD: one work-item takes PRODUCT_LANES consecutive tets, one
// tet per vector lane, with the per-tet data (Dminv, volume, dP/dF) stored
// component-major (x[k·Tp + t]) so that each component is one vector load.
// Only the node gathers and the slot stores are per lane (see the
// eight-tet element kernels above for the layout and padding). With the SIMD the
// product became bound by memory traffic, dP/dF's 81 doubles per tet per
// product (6.3 MB on ICT, measured 0.44 ms): so dP/dF is stored as its
// upper triangle (it is symmetric) in float, 45 floats. That perturbs the
// Newton matrix by about 1e-7 relatively, which only the CG sees; the
// gradient and residuals stay in full precision, so the solution does not.

__kernel void product_tets(const uint T, const uint Tp, __global const int* tets_cm, __global const fsr_real* p,
                           __global const fsr_real* Dminv_cm, __global const fsr_real* vol_p,
                           __global const float* C_cm, __global fsr_real* slots, __global const int* stop) {
  const uint t0 = get_global_id(0) * PRODUCT_LANES;
  if (t0 >= T || stop[0] != 0) return;
  preal pc[12], Dm[9], dF[9], dP[9], y[12];
  gather_corners8(t0, Tp, tets_cm, p, pc);
  #pragma unroll
  for (int k = 0; k < 9; ++k) Dm[k] = pload(Dminv_cm + (size_t)k * Tp + t0);
  fsr8_tet_F(pc, Dm, dF);
  __global const float* C = C_cm + t0;
  #pragma unroll
  for (int r = 0; r < 9; ++r) dP[r] = (preal)(0);
  int m = 0;
  #pragma unroll
  for (int r = 0; r < 9; ++r) {
    dP[r] += CLOAD(C + (size_t)(m++) * Tp) * dF[r];
    #pragma unroll
    for (int c = r + 1; c < 9; ++c) {
      const preal v = CLOAD(C + (size_t)(m++) * Tp);
      dP[r] += v * dF[c];
      dP[c] += v * dF[r];
    }
  }
  fsr8_tet_scatter(dP, Dm, pload(vol_p + t0), y);
  // Stored here rather than by store_tets8: with the count a literal the
  // loop unrolls (this is the CG's hot path).
  fsr_real lane[PRODUCT_LANES];
  const uint n = min((uint)PRODUCT_LANES, T - t0);
  #pragma unroll
  for (int k = 0; k < 12; ++k) {
    pstore(y[k], lane);
    for (uint l = 0; l < n; ++l) slots[12 * (size_t)(t0 + l) + k] = lane[l];
  }
}

// The embedded surface vertices' track-spring products (slots after the tets').
__kernel void product_surface(const uint T, const uint S, __global const fsr_real* p, __global const int* slist,
                              __global const int* sn, __global const fsr_real* sw, __global const fsr_real* surfH,
                              __global fsr_real* slots, __global const int* stop) {
  const uint i = get_global_id(0);
  if (i >= S || stop[0] != 0) return;
  fsr_real q[3], w[4], hq[3];
  surface_point(slist[i], sn, sw, p, q, w);
  __global const fsr_real* H = surfH + 9 * (size_t)i;
  for (int r = 0; r < 3; ++r) hq[r] = H[3 * r] * q[0] + H[3 * r + 1] * q[1] + H[3 * r + 2] * q[2];
  __global fsr_real* out = slots + 12 * ((size_t)T + i);
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 3; ++c) out[3 * k + c] = w[k] * hq[c];
}

// The products' common end: q_v = (s0, sa, sb) for a live node and the
// work-group's partial sum of p·q (every work-item of the group calls it).
void store_product(const bool live, const uint v, const fsr_real s0, const fsr_real sa, const fsr_real sb,
                   __global const fsr_real* p, __global fsr_real* q, __global fsr_real* partial,
                   __local fsr_real* s1) {
  fsr_real acc = 0;
  if (live) {
    q[3 * v] = s0;
    q[3 * v + 1] = sa;
    q[3 * v + 2] = sb;
    acc = p[3 * v] * s0 + p[3 * v + 1] * sa + p[3 * v + 2] * sb;
  }
  s1[get_local_id(0)] = acc;
  group_sum(s1);
  if (get_local_id(0) == 0) partial[get_group_id(0)] = s1[0];
}

// q = gathered slots + L p (bone nodes 0), and partial sums of p·q. L is
// for frames whose only surface terms are the track springs (no point
// springs or spheres): each tracked vertex's Hessian is then k·I, so the
// springs' share of K is L ⊗ I with L = Σ_v k_v w_v w_vᵀ over the embedding
// weights, a fixed node × node matrix (CSR, built at load); folding it in
// here removes the per-vertex product_surface pass and its slots. Other
// frames pass an empty L and the surface vertices' slots.
__kernel void gather_dot(const uint N, __global const int* inc_offset, __global const int* inc_slot,
                               __global const int* L_offset, __global const int* L_col,
                               __global const fsr_real* L_val, __global const uchar* bone,
                               __global const fsr_real* slots, __global fsr_real* q, __global const fsr_real* p,
                               __global fsr_real* partial, __local fsr_real* s1, __global const int* stop) {
  if (stop[0] != 0) return;
  const uint v = get_global_id(0);
  fsr_real s0 = 0, sa = 0, sb = 0;
  if (v < N) {
    if (bone[v] == 0) {
      for (int i = inc_offset[v]; i < inc_offset[v + 1]; ++i) {
        __global const fsr_real* s = SLOT3(slots, inc_slot[i]);
        s0 += s[0];
        sa += s[1];
        sb += s[2];
      }
      for (int i = L_offset[v]; i < L_offset[v + 1]; ++i) {
        const fsr_real l = L_val[i];
        __global const fsr_real* pu = p + 3 * (size_t)L_col[i];
        s0 += l * pu[0];
        sa += l * pu[1];
        sb += l * pu[2];
      }
    }
  }
  store_product(v < N, v, s0, sa, sb, p, q, partial, s1);
}

// ---- The assembled stiffness matrix (engine/sim/stiffness_pattern.h) ----
// K in float 3x3 blocks, block-CSR by node row over the free nodes, summed
// once per Newton step from the tets' blocks (and the surface terms), so that
// each CG product reads K's 1.1 MB instead of recomputing every tet's
// product from dP/dF and gathering its slots.

// Work-item per node: each block of its row summed in full precision from
// its sources (tet_ref here: 2 KE_INDEX(t, 9 pair) + transposed, the
// pattern's refs resolved on the host), then stored in float; the diagonal block's inverse, in full
// precision, is the block-Jacobi preconditioner (zero for bone nodes).
// track_mode 1: the surface share is the track springs' fixed `track` (see
// gather_dot); 0: every surface vertex's Hessian surfH (point springs,
// spheres), weighted by its embedding.
__kernel void assemble_stiffness(const uint N, const int track_mode, __global const int* row_offset,
                                 __global const int* col, __global const int* tet_offset,
                                 __global const int* tet_ref, __global const int* surf_offset,
                                 __global const int* surf_ref, __global const fsr_real* track,
                                 __global const int* slist, __global const fsr_real* sw,
                                 __global const fsr_real* surfH, __global const float* Ke,
                                 __global float* K, __global fsr_real* Minv) {
  const uint v = get_global_id(0);
  if (v >= N) return;
  fsr_real inv[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (int b = row_offset[v]; b < row_offset[v + 1]; ++b) {
    fsr_real A[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int i = tet_offset[b]; i < tet_offset[b + 1]; ++i) {
      const int ref = tet_ref[i];
      __global const float* src = Ke + (ref >> 1);
      if (ref & 1) {
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) A[3 * r + c] += src[PRODUCT_LANES * (3 * c + r)];
      } else {
        for (int e = 0; e < 9; ++e) A[e] += src[PRODUCT_LANES * e];
      }
    }
    if (track_mode) {
      const fsr_real l = track[b];
      A[0] += l;
      A[4] += l;
      A[8] += l;
    } else {
      for (int i = surf_offset[b]; i < surf_offset[b + 1]; ++i) {
        const int ref = surf_ref[i], s = ref >> 4, ca = (ref >> 2) & 3, cb = ref & 3;
        const int vert = slist[s];
        const fsr_real w = sw[4 * vert + ca] * sw[4 * vert + cb];
        for (int e = 0; e < 9; ++e) A[e] += w * surfH[9 * (size_t)s + e];
      }
    }
    for (int e = 0; e < 9; ++e) K[9 * (size_t)b + e] = (float)A[e];
    if (col[b] == (int)v) inverse3_or_zero(A, inv);
  }
  for (int e = 0; e < 9; ++e) Minv[9 * (size_t)v + e] = inv[e];
}

// q = K p (bone rows empty, so 0) and partial sums of p·q: the CG's product
// on the assembled matrix, the same contract as gather_dot.
__kernel void spmv_dot(const uint N, __global const int* row_offset, __global const int* col,
                       __global const float* K, __global const fsr_real* p, __global fsr_real* q,
                       __global fsr_real* partial, __local fsr_real* s1, __global const int* stop) {
  if (stop[0] != 0) return;
  const uint v = get_global_id(0);
  fsr_real s0 = 0, sa = 0, sb = 0;
  if (v < N) {
    for (int b = row_offset[v]; b < row_offset[v + 1]; ++b) {
      __global const float* A = K + 9 * (size_t)b;
      __global const fsr_real* pu = p + 3 * (size_t)col[b];
      const fsr_real p0 = pu[0], p1 = pu[1], p2 = pu[2];
      s0 += A[0] * p0 + A[1] * p1 + A[2] * p2;
      sa += A[3] * p0 + A[4] * p1 + A[5] * p2;
      sb += A[6] * p0 + A[7] * p1 + A[8] * p2;
    }
  }
  store_product(v < N, v, s0, sa, sb, p, q, partial, s1);
}

// One iteration of the single-reduction CG (Chronopoulos and Gear 1989; see
// ClSimulator::pcg) in one launch: the scalar recurrences, then the vector
// work. Each work-group's first work-item forms the scalars from the
// previous iteration's partial sums (u·Ku in `partial`, r·r and r·u
// interleaved in `partial2_in`, `groups` of each), the same operations in
// the same order in every group, so every group gets the same α and β;
// group 0 also records them in cg_out and the state in flags. cg[]: γ, α,
// β, denominator p·Kp, the stopping threshold on |r|; flags[0]: 0 running,
// 1 converged, 2 negative curvature; flags[1]: iterations taken. The
// scalars and partial sums are double-buffered by iteration (the host
// swaps cg_in/cg_out and partial2_in/_out), so no group reads what another
// writes in the same launch. Only first work-items read flags, and group 0
// writes them only when every group stops too, so the groups' barriers are
// never divergent. Then p = u + β p, s = w + β s (s = K p), d += α p,
// r −= α s, u = M⁻¹ r, and partial sums of r·r and r·u; with w = K u from
// the product that follows, all of the next iteration's scalars come from
// one reduction.
__kernel void cg_iteration(const uint N, const uint groups, const int first, __global const fsr_real* partial,
                           __global const fsr_real* partial2_in, __global const fsr_real* cg_in,
                           __global fsr_real* cg_out, __global int* flags, __global fsr_real* u,
                           __global const fsr_real* w, __global fsr_real* p, __global fsr_real* s,
                           __global fsr_real* d, __global fsr_real* r, __global const fsr_real* Minv,
                           __global fsr_real* partial2_out, __local fsr_real* s1, __local fsr_real* s2) {
  __local int state_l[1];
  __local fsr_real ab_l[2];
  const uint v = get_global_id(0), lid = get_local_id(0);
  if (lid == 0) {
    const int was = flags[0];
    int state = was;
    fsr_real gamma = cg_in[0], alpha = cg_in[1], beta = cg_in[2], denom = cg_in[3];
    if (state == 0 && !first) {
      fsr_real delta = 0, rr = 0, gamma1 = 0;
      for (uint i = 0; i < groups; ++i) delta += partial[i];
      for (uint i = 0; i < groups; ++i) {
        rr += partial2_in[2 * i];
        gamma1 += partial2_in[2 * i + 1];
      }
      if (sqrt(rr) <= cg_in[4]) {
        state = 1;
      } else {
        beta = gamma1 / gamma;
        denom = delta - beta * gamma1 / alpha;
        gamma = gamma1;
      }
    }
    if (state == 0 && !(denom > 0)) state = 2;
    if (state == 0) alpha = gamma / denom;
    if (get_group_id(0) == 0 && was == 0) {
      if (state != 0) {
        flags[0] = state;
      } else {
        cg_out[0] = gamma;
        cg_out[1] = alpha;
        cg_out[2] = beta;
        cg_out[3] = denom;
        cg_out[4] = cg_in[4];
        flags[1] += 1;
      }
    }
    state_l[0] = state;
    ab_l[0] = alpha;
    ab_l[1] = beta;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int state = state_l[0];
  const fsr_real alpha = ab_l[0], beta = ab_l[1];
  fsr_real rr = 0, ru = 0;
  if (state == 0 && v < N) {
    fsr_real rv[3];
    for (int c = 0; c < 3; ++c) {
      const size_t i = 3 * (size_t)v + c;
      const fsr_real pi = u[i] + beta * p[i], si = w[i] + beta * s[i];
      p[i] = pi;
      s[i] = si;
      d[i] += alpha * pi;
      rv[c] = r[i] - alpha * si;
      r[i] = rv[c];
    }
    __global const fsr_real* M = Minv + 9 * (size_t)v;
    for (int i = 0; i < 3; ++i) {
      const fsr_real ui = M[3 * i] * rv[0] + M[3 * i + 1] * rv[1] + M[3 * i + 2] * rv[2];
      u[3 * v + i] = ui;
      rr += rv[i] * rv[i];
      ru += rv[i] * ui;
    }
  }
  s1[lid] = rr;
  s2[lid] = ru;
  group_sum2(s1, s2);
  if (lid == 0 && state == 0) {
    partial2_out[2 * get_group_id(0)] = s1[0];
    partial2_out[2 * get_group_id(0) + 1] = s2[0];
  }
}

// Warm start for the next frame by linear extrapolation of the last two:
// x ← 2x − x_prev, x_prev ← x (old).
__kernel void extrapolate(const uint n, __global fsr_real* x, __global fsr_real* x_prev) {
  const uint i = get_global_id(0);
  if (i >= n) return;
  const fsr_real xi = x[i];
  x[i] = 2 * xi - x_prev[i];
  x_prev[i] = xi;
}
