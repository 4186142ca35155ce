// Teran muscle material, shared verbatim by the OpenCL kernels (cl/sim.cl)
// and the C++ CPU reference (engine/sim). One source for the formulas is what
// makes the OpenCL/CPU parity tests meaningful.
//
// Written in the common subset of C99 and OpenCL C 1.2: plain functions on
// private arrays, 3x3 matrices row-major (M[3*i+j]), no address-space
// qualifiers. Units: lengths cm, stresses kPa, energies kPa·cm³ (mJ).
//
// Energy density of one tet (Teran et al. 2003; invertible form after Teran
// et al. 2005):
//   Ψ = μ10 (Ī1 − 3) + μ01 (Ī2 − 3) + κ/2 (J − 1)² + φ Ψ_fibre(λ; α)
//   Ī1 = h(J)^(-2/3) I1,  Ī2 = h(J)^(-4/3) I2,  λ = |F a|
// h(J) = J above j_min and a smooth positive floor below, so the deviatoric
// invariants stay finite for degenerate and inverted tets while the
// volumetric term keeps pushing them back; the energy is C1 in F everywhere
// and smooth away from J = j_min.
// Ψ_fibre' = σ_max (α f_active(λ) + f_passive(λ)) with Blemker's (2005)
// force-length curve (parabolic pieces joined C1) and an exponential passive
// stiffening that starts with zero slope at λ = 1, so the rest pose is a
// smooth stress-free minimum.
//
// Stress and stiffness are evaluated on the diagonal: F = U Σ Vᵀ with U, V
// rotations (the rotation-variant SVD: an inverted tet gets σ3 < 0). The
// definiteness fix projects the 3x3 block and the three 2x2 shear blocks of
// the isotropic dP/dF onto PSD, and the two coefficients of the fibre term
// (along and across the fibre) onto ≥ 0; the sum is PSD.
#ifndef FSR_MATERIAL_H
#define FSR_MATERIAL_H

#ifdef __OPENCL_VERSION__
#ifdef FSR_REAL_FLOAT
typedef float fsr_real;
#else
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double fsr_real;
#endif
#define FSR_FN
// PoCL does not unroll these fixed-count loops by itself, and without
// unrolling every small array stays in memory (measured: the stiffness
// product ran 1.8× slower); the C++ compiler unrolls them on its own.
#define FSR_UNROLL _Pragma("unroll")
#else
typedef double fsr_real;
#define FSR_FN static inline
#define FSR_UNROLL
#endif

typedef struct {
  fsr_real mu10;         // kPa, Mooney-Rivlin first invariant
  fsr_real mu01;         // kPa, Mooney-Rivlin second invariant
  fsr_real kappa;        // kPa, bulk modulus of the volumetric penalty
  fsr_real j_min;        // below this J the deviatoric part sees a floored J
  fsr_real sigma_max;    // kPa, peak fibre stress (active, α = 1)
  fsr_real p1, p2;       // passive fibre stiffening (Blemker 2005)
  fsr_real stretch_lin;  // fibre stretch beyond which passive stress is linear
} fsr_material;

FSR_FN void fsr_mat3_mul(const fsr_real* A, const fsr_real* B, fsr_real* C) {
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

FSR_FN fsr_real fsr_det3(const fsr_real* F) {
  return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) + F[2] * (F[3] * F[7] - F[4] * F[6]);
}

// Eigen-decomposition of a symmetric 3x3 (A is overwritten) by cyclic
// Jacobi rotations: branch-light and accurate, suits both CPU and GPU. Q gets
// the eigenvectors as columns, w the eigenvalues (unsorted).
FSR_FN void fsr_sym_eig3(fsr_real* A, fsr_real* Q, fsr_real* w) {
  FSR_UNROLL for (int i = 0; i < 9; ++i) Q[i] = (i % 4 == 0) ? 1 : 0;
  for (int sweep = 0; sweep < 12; ++sweep) {
    const fsr_real off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
    const fsr_real diag = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
    if (off <= (fsr_real)1e-34 * diag || off == 0) break;
    FSR_UNROLL for (int pair = 0; pair < 3; ++pair) {
      const int p = pair == 2 ? 1 : 0, q = pair == 0 ? 1 : 2;
      const fsr_real apq = A[3 * p + q];
      if (apq == 0) continue;
      const fsr_real theta = (A[3 * q + q] - A[3 * p + p]) / (2 * apq);
      fsr_real t;
      if (fabs(theta) > (fsr_real)1e15)
        t = (fsr_real)0.5 / theta;
      else
        t = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
      const fsr_real c = 1 / sqrt(t * t + 1), s = t * c;
      A[3 * p + p] -= t * apq;
      A[3 * q + q] += t * apq;
      A[3 * p + q] = A[3 * q + p] = 0;
      const int r = 3 - p - q;
      const fsr_real arp = A[3 * r + p], arq = A[3 * r + q];
      A[3 * r + p] = A[3 * p + r] = c * arp - s * arq;
      A[3 * r + q] = A[3 * q + r] = s * arp + c * arq;
      FSR_UNROLL for (int k = 0; k < 3; ++k) {
        const fsr_real qkp = Q[3 * k + p], qkq = Q[3 * k + q];
        Q[3 * k + p] = c * qkp - s * qkq;
        Q[3 * k + q] = s * qkp + c * qkq;
      }
    }
  }
  w[0] = A[0];
  w[1] = A[4];
  w[2] = A[8];
}

// Rotation-variant SVD: F = U diag(s) Vᵀ, det U = det V = +1,
// s[0] ≥ s[1] ≥ |s[2]|, and s[2] < 0 exactly when det F < 0.
FSR_FN void fsr_svd3(const fsr_real* F, fsr_real* U, fsr_real* s, fsr_real* V) {
  fsr_real A[9], w[3];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) A[3 * i + j] = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
  fsr_sym_eig3(A, V, w);
  // Sort eigenvalues (and V's columns) descending.
  FSR_UNROLL for (int i = 0; i < 2; ++i)
    FSR_UNROLL for (int j = 0; j < 2 - i; ++j)
      if (w[j] < w[j + 1]) {
        const fsr_real tw = w[j];
        w[j] = w[j + 1];
        w[j + 1] = tw;
        FSR_UNROLL for (int k = 0; k < 3; ++k) {
          const fsr_real tv = V[3 * k + j];
          V[3 * k + j] = V[3 * k + j + 1];
          V[3 * k + j + 1] = tv;
        }
      }
  if (fsr_det3(V) < 0)
    FSR_UNROLL for (int k = 0; k < 3; ++k) V[3 * k + 2] = -V[3 * k + 2];
  // B = F V has orthogonal columns U diag(s); orthonormalise them in order and
  // close with a cross product so that U is a rotation and s[2] carries the sign.
  fsr_real B[9];
  fsr_mat3_mul(F, V, B);
  fsr_real b0[3] = {B[0], B[3], B[6]}, b1[3] = {B[1], B[4], B[7]}, b2[3] = {B[2], B[5], B[8]};
  fsr_real u0[3], u1[3], u2[3];
  const fsr_real n0 = sqrt(b0[0] * b0[0] + b0[1] * b0[1] + b0[2] * b0[2]);
  if (n0 > (fsr_real)1e-30) {
    FSR_UNROLL for (int k = 0; k < 3; ++k) u0[k] = b0[k] / n0;
  } else {
    u0[0] = 1;
    u0[1] = 0;
    u0[2] = 0;
  }
  const fsr_real d01 = u0[0] * b1[0] + u0[1] * b1[1] + u0[2] * b1[2];
  FSR_UNROLL for (int k = 0; k < 3; ++k) u1[k] = b1[k] - d01 * u0[k];
  fsr_real n1 = sqrt(u1[0] * u1[0] + u1[1] * u1[1] + u1[2] * u1[2]);
  if (n1 <= (fsr_real)1e-12 * (n0 + (fsr_real)1e-30)) {
    // Rank ≤ 1: any unit vector orthogonal to u0 will do.
    const int m = (fabs(u0[0]) <= fabs(u0[1]) && fabs(u0[0]) <= fabs(u0[2])) ? 0 : (fabs(u0[1]) <= fabs(u0[2]) ? 1 : 2);
    fsr_real e[3] = {0, 0, 0};
    e[m] = 1;
    u1[0] = u0[1] * e[2] - u0[2] * e[1];
    u1[1] = u0[2] * e[0] - u0[0] * e[2];
    u1[2] = u0[0] * e[1] - u0[1] * e[0];
    n1 = sqrt(u1[0] * u1[0] + u1[1] * u1[1] + u1[2] * u1[2]);
  }
  FSR_UNROLL for (int k = 0; k < 3; ++k) u1[k] /= n1;
  u2[0] = u0[1] * u1[2] - u0[2] * u1[1];
  u2[1] = u0[2] * u1[0] - u0[0] * u1[2];
  u2[2] = u0[0] * u1[1] - u0[1] * u1[0];
  s[0] = u0[0] * b0[0] + u0[1] * b0[1] + u0[2] * b0[2];
  s[1] = u1[0] * b1[0] + u1[1] * b1[1] + u1[2] * b1[2];
  s[2] = u2[0] * b2[0] + u2[1] * b2[1] + u2[2] * b2[2];
  FSR_UNROLL for (int k = 0; k < 3; ++k) {
    U[3 * k] = u0[k];
    U[3 * k + 1] = u1[k];
    U[3 * k + 2] = u2[k];
  }
}

// h(J) and its first two derivatives: identity above j_min, above j_min/2 always.
FSR_FN void fsr_jfloor(fsr_real J, fsr_real c, fsr_real* h, fsr_real* dh, fsr_real* ddh) {
  if (J >= c) {
    *h = J;
    *dh = 1;
    *ddh = 0;
  } else {
    const fsr_real e = exp(2 * (J - c) / c);
    *h = (fsr_real)0.5 * c * (1 + e);
    *dh = e;
    *ddh = 2 * e / c;
  }
}

// f = h^(-2/3), g = h^(-4/3) as functions of J, with first and second derivatives.
FSR_FN void fsr_dev_factors(const fsr_material* m, fsr_real J, fsr_real* f, fsr_real* g) {
  fsr_real h, dh, ddh;
  fsr_jfloor(J, m->j_min, &h, &dh, &ddh);
  const fsr_real cb = cbrt(h);
  f[0] = 1 / (cb * cb);
  g[0] = f[0] * f[0];
  f[1] = -(fsr_real)2 / 3 * f[0] / h * dh;
  g[1] = -(fsr_real)4 / 3 * g[0] / h * dh;
  f[2] = (fsr_real)10 / 9 * f[0] / (h * h) * dh * dh - (fsr_real)2 / 3 * f[0] / h * ddh;
  g[2] = (fsr_real)28 / 9 * g[0] / (h * h) * dh * dh - (fsr_real)4 / 3 * g[0] / h * ddh;
}

// Isotropic energy density from the invariants of F (no SVD needed).
FSR_FN fsr_real fsr_iso_energy_F(const fsr_material* m, const fsr_real* F) {
  fsr_real C[9];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) C[3 * i + j] = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
  const fsr_real I1 = C[0] + C[4] + C[8];
  fsr_real trC2 = 0;
  FSR_UNROLL for (int i = 0; i < 9; ++i) trC2 += C[i] * C[i];
  const fsr_real I2 = (fsr_real)0.5 * (I1 * I1 - trC2);
  const fsr_real J = fsr_det3(F);
  fsr_real f[3], g[3];
  fsr_dev_factors(m, J, f, g);
  return m->mu10 * (f[0] * I1 - 3) + m->mu01 * (g[0] * I2 - 3) + (fsr_real)0.5 * m->kappa * (J - 1) * (J - 1);
}

// Isotropic part on the diagonal: P̂ = ∂Ψ/∂σ, H = ∂²Ψ/∂σ², and for the pairs
// (0,1), (0,2), (1,2) the eigenvalues of the 2x2 shear blocks:
// lam[2p] = (P̂i − P̂j)/(σi − σj), lam[2p+1] = (P̂i + P̂j)/(σi + σj), in closed
// form so that repeated or opposite singular values need no special case.
FSR_FN void fsr_iso_diag(const fsr_material* m, const fsr_real* s, fsr_real* P, fsr_real* H, fsr_real* lam) {
  const fsr_real J = s[0] * s[1] * s[2];
  const fsr_real s2[3] = {s[0] * s[0], s[1] * s[1], s[2] * s[2]};
  const fsr_real S = s2[0] + s2[1] + s2[2];
  const fsr_real I1 = S;
  const fsr_real I2 = s2[0] * s2[1] + s2[0] * s2[2] + s2[1] * s2[2];
  fsr_real f[3], g[3];
  fsr_dev_factors(m, J, f, g);
  const fsr_real Jd[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
  fsr_real I2d[3];
  FSR_UNROLL for (int i = 0; i < 3; ++i) I2d[i] = 2 * s[i] * (S - s2[i]);
  const fsr_real A = m->mu10 * f[1] * I1 + m->mu01 * g[1] * I2 + m->kappa * (J - 1);
  FSR_UNROLL for (int i = 0; i < 3; ++i) P[i] = A * Jd[i] + 2 * m->mu10 * f[0] * s[i] + m->mu01 * g[0] * I2d[i];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) {
      const fsr_real Jij = i == j ? 0 : s[3 - i - j];
      const fsr_real I1ij = i == j ? 2 : 0;
      const fsr_real I2ij = i == j ? 2 * (S - s2[i]) : 4 * s[i] * s[j];
      const fsr_real I1i = 2 * s[i], I1j = 2 * s[j];
      H[3 * i + j] =
          m->mu10 * (f[2] * Jd[i] * Jd[j] * I1 + f[1] * (Jij * I1 + Jd[i] * I1j + Jd[j] * I1i) + f[0] * I1ij) +
          m->mu01 * (g[2] * Jd[i] * Jd[j] * I2 + g[1] * (Jij * I2 + Jd[i] * I2d[j] + Jd[j] * I2d[i]) + g[0] * I2ij) +
          m->kappa * (Jd[i] * Jd[j] + (J - 1) * Jij);
    }
  FSR_UNROLL for (int p = 0; p < 3; ++p) {
    const int i = p == 2 ? 1 : 0, j = p == 0 ? 1 : 2, k = 3 - i - j;
    lam[2 * p] = -A * s[k] + 2 * m->mu10 * f[0] + 2 * m->mu01 * g[0] * (s2[k] - s[i] * s[j]);
    lam[2 * p + 1] = A * s[k] + 2 * m->mu10 * f[0] + 2 * m->mu01 * g[0] * (s2[k] + s[i] * s[j]);
  }
}

// Blemker's active force-length curve with its outer parabolas moved so the
// curve is C1: f = 1 − 4(λ−1)² on [0.6, 1.4], (64/9)(λ − 0.375)² below,
// (64/9)(λ − 1.625)² above, zero outside (0.375, 1.625). Returns the integral
// from 1 to λ, and f and f' through out-parameters.
FSR_FN fsr_real fsr_active_curve(fsr_real l, fsr_real* f, fsr_real* df) {
  const fsr_real a = (fsr_real)64 / 9, lo = (fsr_real)0.375, hi = (fsr_real)1.625;
  // Antiderivative measured from lo; its value at 1 is subtracted at the end.
  const fsr_real F06 = (fsr_real)0.027, F14 = (fsr_real)0.027 + (fsr_real)0.8 - (fsr_real)4 / 3 * (fsr_real)0.128;
  const fsr_real F1 = (fsr_real)0.027 + (fsr_real)0.4 - (fsr_real)4 / 3 * (fsr_real)0.064;
  fsr_real Fl;
  if (l <= lo) {
    *f = 0;
    *df = 0;
    Fl = 0;
  } else if (l <= (fsr_real)0.6) {
    *f = a * (l - lo) * (l - lo);
    *df = 2 * a * (l - lo);
    Fl = a / 3 * (l - lo) * (l - lo) * (l - lo);
  } else if (l <= (fsr_real)1.4) {
    const fsr_real x = l - 1;
    *f = 1 - 4 * x * x;
    *df = -8 * x;
    Fl = F06 + (l - (fsr_real)0.6) - (fsr_real)4 / 3 * (x * x * x + (fsr_real)0.064);
  } else if (l <= hi) {
    *f = a * (l - hi) * (l - hi);
    *df = 2 * a * (l - hi);
    const fsr_real c = (fsr_real)0.225;
    Fl = F14 + a / 3 * ((l - hi) * (l - hi) * (l - hi) + c * c * c);
  } else {
    *f = 0;
    *df = 0;
    const fsr_real c = (fsr_real)0.225;
    Fl = F14 + a / 3 * c * c * c;
  }
  return Fl - F1;
}

// Passive fibre stiffening: f = p1 (exp(p2 x) − 1 − p2 x), x = λ − 1 > 0,
// continued linearly beyond stretch_lin. Returns the integral from 1 to λ.
FSR_FN fsr_real fsr_passive_curve(const fsr_material* m, fsr_real l, fsr_real* f, fsr_real* df) {
  if (l <= 1) {
    *f = 0;
    *df = 0;
    return 0;
  }
  const fsr_real xs = m->stretch_lin - 1;
  const fsr_real x = l - 1, xe = x < xs ? x : xs;
  const fsr_real e = exp(m->p2 * xe);
  const fsr_real fe = m->p1 * (e - 1 - m->p2 * xe);
  const fsr_real dfe = m->p1 * m->p2 * (e - 1);
  const fsr_real Fe = m->p1 * ((e - 1) / m->p2 - xe - (fsr_real)0.5 * m->p2 * xe * xe);
  if (x <= xs) {
    *f = fe;
    *df = dfe;
    return Fe;
  }
  const fsr_real d = x - xs;
  *f = fe + dfe * d;
  *df = dfe;
  return Fe + fe * d + (fsr_real)0.5 * dfe * d * d;
}

// Fibre energy density φ Ψ_fibre(λ) and its first two derivatives in λ.
FSR_FN fsr_real fsr_fibre(const fsr_material* m, fsr_real l, fsr_real alpha, fsr_real phi, fsr_real* d1, fsr_real* d2) {
  fsr_real fa, dfa, fp, dfp;
  const fsr_real Ea = fsr_active_curve(l, &fa, &dfa);
  const fsr_real Ep = fsr_passive_curve(m, l, &fp, &dfp);
  const fsr_real k = phi * m->sigma_max;
  *d1 = k * (alpha * fa + fp);
  *d2 = k * (alpha * dfa + dfp);
  return k * (alpha * Ea + Ep);
}

// Energy density Ψ(F) of a tet with unit fibre a, muscle fraction phi and activation alpha.
FSR_FN fsr_real fsr_energy_density(const fsr_material* m, const fsr_real* F, const fsr_real* a, fsr_real phi,
                                   fsr_real alpha) {
  fsr_real psi = fsr_iso_energy_F(m, F);
  if (phi > 0) {
    const fsr_real Fa[3] = {F[0] * a[0] + F[1] * a[1] + F[2] * a[2], F[3] * a[0] + F[4] * a[1] + F[5] * a[2],
                            F[6] * a[0] + F[7] * a[1] + F[8] * a[2]};
    const fsr_real l = sqrt(Fa[0] * Fa[0] + Fa[1] * Fa[1] + Fa[2] * Fa[2]);
    fsr_real d1, d2;
    psi += fsr_fibre(m, l, alpha, phi, &d1, &d2);
  }
  return psi;
}

// First Piola-Kirchhoff stress P = ∂Ψ/∂F.
FSR_FN void fsr_stress(const fsr_material* m, const fsr_real* F, const fsr_real* a, fsr_real phi, fsr_real alpha,
                       fsr_real* P) {
  fsr_real U[9], s[3], V[9], Ph[3], H[9], lam[6];
  fsr_svd3(F, U, s, V);
  fsr_iso_diag(m, s, Ph, H, lam);
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j)
      P[3 * i + j] = U[3 * i] * Ph[0] * V[3 * j] + U[3 * i + 1] * Ph[1] * V[3 * j + 1] + U[3 * i + 2] * Ph[2] * V[3 * j + 2];
  if (phi > 0) {
    const fsr_real Fa[3] = {F[0] * a[0] + F[1] * a[1] + F[2] * a[2], F[3] * a[0] + F[4] * a[1] + F[5] * a[2],
                            F[6] * a[0] + F[7] * a[1] + F[8] * a[2]};
    const fsr_real l = sqrt(Fa[0] * Fa[0] + Fa[1] * Fa[1] + Fa[2] * Fa[2]);
    if (l > (fsr_real)1e-12) {
      fsr_real d1, d2;
      fsr_fibre(m, l, alpha, phi, &d1, &d2);
      FSR_UNROLL for (int i = 0; i < 3; ++i)
        FSR_UNROLL for (int j = 0; j < 3; ++j) P[3 * i + j] += d1 * Fa[i] / l * a[j];
    }
  }
}

// Projects a symmetric 3x3 onto the PSD cone (negative eigenvalues → 0).
FSR_FN void fsr_psd3(fsr_real* H) {
  fsr_real A[9], Q[9], w[3];
  FSR_UNROLL for (int i = 0; i < 9; ++i) A[i] = H[i];
  fsr_sym_eig3(A, Q, w);
  FSR_UNROLL for (int k = 0; k < 3; ++k) w[k] = w[k] > 0 ? w[k] : 0;
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j)
      H[3 * i + j] = Q[3 * i] * w[0] * Q[3 * j] + Q[3 * i + 1] * w[1] * Q[3 * j + 1] + Q[3 * i + 2] * w[2] * Q[3 * j + 2];
}

// dP/dF as a 9x9 matrix: δP[r] = Σ_c C[9r + c] δF[c], with r, c = 3i + j.
// fix != 0 applies the definiteness fix, making C symmetric PSD.
FSR_FN void fsr_stress_derivative(const fsr_material* m, const fsr_real* F, const fsr_real* a, fsr_real phi,
                                  fsr_real alpha, int fix, fsr_real* C) {
  fsr_real U[9], s[3], V[9], Ph[3], H[9], lam[6];
  fsr_svd3(F, U, s, V);
  fsr_iso_diag(m, s, Ph, H, lam);
  if (fix) {
    fsr_psd3(H);
    FSR_UNROLL for (int k = 0; k < 6; ++k) lam[k] = lam[k] > 0 ? lam[k] : 0;
  }
  FSR_UNROLL for (int cd = 0; cd < 9; ++cd) {
    const int c = cd / 3, d = cd % 3;
    // δF = e_c e_dᵀ seen in the diagonal frame: δF̂ = Uᵀ δF V.
    fsr_real dFh[9], dPh[9];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int j = 0; j < 3; ++j) dFh[3 * i + j] = U[3 * c + i] * V[3 * d + j];
    FSR_UNROLL for (int i = 0; i < 3; ++i) dPh[4 * i] = H[3 * i] * dFh[0] + H[3 * i + 1] * dFh[4] + H[3 * i + 2] * dFh[8];
    FSR_UNROLL for (int p = 0; p < 3; ++p) {
      const int i = p == 2 ? 1 : 0, j = p == 0 ? 1 : 2;
      const fsr_real ab = (fsr_real)0.5 * (lam[2 * p] + lam[2 * p + 1]);
      const fsr_real bb = (fsr_real)0.5 * (lam[2 * p] - lam[2 * p + 1]);
      dPh[3 * i + j] = ab * dFh[3 * i + j] + bb * dFh[3 * j + i];
      dPh[3 * j + i] = bb * dFh[3 * i + j] + ab * dFh[3 * j + i];
    }
    // δP = U δP̂ Vᵀ
    fsr_real T[9];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int j = 0; j < 3; ++j) T[3 * i + j] = U[3 * i] * dPh[j] + U[3 * i + 1] * dPh[3 + j] + U[3 * i + 2] * dPh[6 + j];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int j = 0; j < 3; ++j)
        C[9 * (3 * i + j) + cd] = T[3 * i] * V[3 * j] + T[3 * i + 1] * V[3 * j + 1] + T[3 * i + 2] * V[3 * j + 2];
  }
  if (phi > 0) {
    const fsr_real Fa[3] = {F[0] * a[0] + F[1] * a[1] + F[2] * a[2], F[3] * a[0] + F[4] * a[1] + F[5] * a[2],
                            F[6] * a[0] + F[7] * a[1] + F[8] * a[2]};
    const fsr_real l = sqrt(Fa[0] * Fa[0] + Fa[1] * Fa[1] + Fa[2] * Fa[2]);
    if (l > (fsr_real)1e-12) {
      fsr_real d1, d2;
      fsr_fibre(m, l, alpha, phi, &d1, &d2);
      fsr_real along = d2, across = d1 / l;
      if (fix) {
        along = along > 0 ? along : 0;
        across = across > 0 ? across : 0;
      }
      const fsr_real dv[3] = {Fa[0] / l, Fa[1] / l, Fa[2] / l};
      FSR_UNROLL for (int i = 0; i < 3; ++i)
        FSR_UNROLL for (int j = 0; j < 3; ++j)
          FSR_UNROLL for (int k = 0; k < 3; ++k)
            FSR_UNROLL for (int q = 0; q < 3; ++q)
              C[9 * (3 * i + j) + 3 * k + q] +=
                  (along * dv[i] * dv[k] + across * ((i == k ? 1 : 0) - dv[i] * dv[k])) * a[j] * a[q];
    }
  }
}

// F = Ds Dm⁻¹ for corner positions x[12] (corner-major).
FSR_FN void fsr_tet_F(const fsr_real* x, const fsr_real* Dminv, fsr_real* F) {
  fsr_real Ds[9];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) Ds[3 * i + j] = x[3 * (j + 1) + i] - x[i];
  fsr_mat3_mul(Ds, Dminv, F);
}

// Energy gradient of a tet at its corners, g[12] = vol · ∂Ψ/∂x, from the
// matrix G = vol · P Dm⁻ᵀ (gradient of corners 1..3; corner 0 balances them).
// Used for forces (−g) and, with δP, for stiffness products.
FSR_FN void fsr_tet_scatter(const fsr_real* P, const fsr_real* Dminv, fsr_real vol, fsr_real* g) {
  FSR_UNROLL for (int i = 0; i < 3; ++i) {
    fsr_real sum = 0;
    FSR_UNROLL for (int c = 0; c < 3; ++c) {
      const fsr_real v = vol * (P[3 * i] * Dminv[3 * c] + P[3 * i + 1] * Dminv[3 * c + 1] + P[3 * i + 2] * Dminv[3 * c + 2]);
      g[3 * (c + 1) + i] = v;
      sum += v;
    }
    g[i] = -sum;
  }
}

// y[12] = K dx for the tet's stiffness K = vol · Bᵀ C B (B: corners → F).
FSR_FN void fsr_tet_stiffness_product(const fsr_real* C, const fsr_real* Dminv, fsr_real vol, const fsr_real* dx,
                                      fsr_real* y) {
  fsr_real dF[9], dP[9];
  fsr_tet_F(dx, Dminv, dF);
  FSR_UNROLL for (int r = 0; r < 9; ++r) {
    fsr_real sum = 0;
    FSR_UNROLL for (int c = 0; c < 9; ++c) sum += C[9 * r + c] * dF[c];
    dP[r] = sum;
  }
  fsr_tet_scatter(dP, Dminv, vol, y);
}

// The four 3x3 diagonal blocks of K (corner-major, D[9k + 3i + j]), for the
// block-Jacobi preconditioner.
FSR_FN void fsr_tet_diag_blocks(const fsr_real* C, const fsr_real* Dminv, fsr_real vol, fsr_real* D) {
  // B for corner k maps δx_k (3) to δF: δF[3i + j] = δx_k[i] · b_k[j], with
  // b_k = row k−1 of Dm⁻¹ for k ≥ 1 and b_0 = −(sum of rows).
  FSR_UNROLL for (int k = 0; k < 4; ++k) {
    fsr_real b[3];
    FSR_UNROLL for (int j = 0; j < 3; ++j)
      b[j] = k == 0 ? -(Dminv[j] + Dminv[3 + j] + Dminv[6 + j]) : Dminv[3 * (k - 1) + j];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int l = 0; l < 3; ++l) {
        fsr_real sum = 0;
        FSR_UNROLL for (int j = 0; j < 3; ++j)
          FSR_UNROLL for (int q = 0; q < 3; ++q) sum += b[j] * C[9 * (3 * i + j) + 3 * l + q] * b[q];
        D[9 * k + 3 * i + l] = vol * sum;
      }
  }
}

#endif  // FSR_MATERIAL_H
