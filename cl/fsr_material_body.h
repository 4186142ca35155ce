// The Teran material's functions (formulas: see cl/fsr_material.h), written
// once for any value type and included once per type, with no include guard:
//   FSR_T        the value type: a scalar (C++ and OpenCL) or an OpenCL
//                vector whose lanes are independent tets (cl/sim.cl)
//   FSR(name)    the instantiated function's name
//   FSR_IF(c, a, b)  per lane: a where the mask c holds, else b
//   FSR_ALL(c)   whether the mask holds in every lane
// Data-dependent choices are therefore selections, not branches, so the same
// source runs one tet per lane; both sides of a selection are computed, and
// the side not taken may be inf or NaN without harm. Only the Jacobi sweep
// count is a loop test (it stops once every lane has converged; lanes that
// converged earlier see identity rotations, so every lane gets the result
// that the scalar code gets).
#define FSR_C(v) ((FSR_T)(v))

FSR_FN void FSR(mat3_mul)(const FSR_T* A, const FSR_T* B, FSR_T* C) {
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

FSR_FN FSR_T FSR(det3)(const FSR_T* F) {
  return F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) + F[2] * (F[3] * F[7] - F[4] * F[6]);
}

// Eigen-decomposition of a symmetric 3x3 (A is overwritten) by cyclic
// Jacobi rotations: branch-light and accurate, suits both CPU and GPU. Q gets
// the eigenvectors as columns, w the eigenvalues (unsorted).
FSR_FN void FSR(sym_eig3)(FSR_T* A, FSR_T* Q, FSR_T* w) {
  FSR_UNROLL for (int i = 0; i < 9; ++i) Q[i] = FSR_C(i % 4 == 0 ? 1 : 0);
  for (int sweep = 0; sweep < 12; ++sweep) {
    const FSR_T off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
    const FSR_T diag = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
    const FSR_M done = off <= (fsr_real)1e-34 * diag || off == 0;
    if (FSR_ALL(done)) break;
    FSR_UNROLL for (int pair = 0; pair < 3; ++pair) {
      const int p = pair == 2 ? 1 : 0, q = pair == 0 ? 1 : 2;
      const FSR_T apq = A[3 * p + q];
      const FSR_M skip = done || apq == 0;
      const FSR_T theta = (A[3 * q + q] - A[3 * p + p]) / (2 * apq);
      const FSR_T t_small = FSR_IF(theta >= 0, FSR_C(1), FSR_C(-1)) / (fabs(theta) + sqrt(theta * theta + 1));
      const FSR_T t_big = FSR_IF(fabs(theta) > (fsr_real)1e15, (fsr_real)0.5 / theta, t_small);
      const FSR_T t = FSR_IF(skip, FSR_C(0), t_big);
      const FSR_T c = 1 / sqrt(t * t + 1), s = t * c;
      A[3 * p + p] -= t * apq;
      A[3 * q + q] += t * apq;
      A[3 * p + q] = A[3 * q + p] = FSR_IF(skip, apq, FSR_C(0));
      const int r = 3 - p - q;
      const FSR_T arp = A[3 * r + p], arq = A[3 * r + q];
      A[3 * r + p] = A[3 * p + r] = c * arp - s * arq;
      A[3 * r + q] = A[3 * q + r] = s * arp + c * arq;
      FSR_UNROLL for (int k = 0; k < 3; ++k) {
        const FSR_T qkp = Q[3 * k + p], qkq = Q[3 * k + q];
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
FSR_FN void FSR(svd3)(const FSR_T* F, FSR_T* U, FSR_T* s, FSR_T* V) {
  FSR_T A[9], w[3];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) A[3 * i + j] = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
  FSR(sym_eig3)(A, V, w);
  // Sort eigenvalues (and V's columns) descending.
  FSR_UNROLL for (int i = 0; i < 2; ++i)
    FSR_UNROLL for (int j = 0; j < 2 - i; ++j) {
      const FSR_M swap = w[j] < w[j + 1];
      const FSR_T wj = w[j];
      w[j] = FSR_IF(swap, w[j + 1], wj);
      w[j + 1] = FSR_IF(swap, wj, w[j + 1]);
      FSR_UNROLL for (int k = 0; k < 3; ++k) {
        const FSR_T vj = V[3 * k + j];
        V[3 * k + j] = FSR_IF(swap, V[3 * k + j + 1], vj);
        V[3 * k + j + 1] = FSR_IF(swap, vj, V[3 * k + j + 1]);
      }
    }
  const FSR_M flip = FSR(det3)(V) < 0;
  FSR_UNROLL for (int k = 0; k < 3; ++k) V[3 * k + 2] = FSR_IF(flip, -V[3 * k + 2], V[3 * k + 2]);
  // B = F V has orthogonal columns U diag(s); orthonormalise them in order and
  // close with a cross product so that U is a rotation and s[2] carries the sign.
  FSR_T B[9];
  FSR(mat3_mul)(F, V, B);
  const FSR_T b0[3] = {B[0], B[3], B[6]}, b1[3] = {B[1], B[4], B[7]}, b2[3] = {B[2], B[5], B[8]};
  FSR_T u0[3], u1[3], u2[3];
  const FSR_T n0 = sqrt(b0[0] * b0[0] + b0[1] * b0[1] + b0[2] * b0[2]);
  const FSR_M has0 = n0 > (fsr_real)1e-30;
  FSR_UNROLL for (int k = 0; k < 3; ++k) u0[k] = FSR_IF(has0, b0[k] / n0, FSR_C(k == 0 ? 1 : 0));
  const FSR_T d01 = u0[0] * b1[0] + u0[1] * b1[1] + u0[2] * b1[2];
  FSR_UNROLL for (int k = 0; k < 3; ++k) u1[k] = b1[k] - d01 * u0[k];
  const FSR_T n1 = sqrt(u1[0] * u1[0] + u1[1] * u1[1] + u1[2] * u1[2]);
  // Rank ≤ 1: any unit vector orthogonal to u0 will do; take u0 × e_m, e_m
  // the axis of u0's smallest component.
  const FSR_M rank1 = n1 <= (fsr_real)1e-12 * (n0 + (fsr_real)1e-30);
  const FSR_M m0 = fabs(u0[0]) <= fabs(u0[1]) && fabs(u0[0]) <= fabs(u0[2]);
  const FSR_M m1 = !m0 && fabs(u0[1]) <= fabs(u0[2]);
  const FSR_T e[3] = {FSR_IF(m0, FSR_C(1), FSR_C(0)), FSR_IF(m1, FSR_C(1), FSR_C(0)),
                      FSR_IF(m0 || m1, FSR_C(0), FSR_C(1))};
  const FSR_T c1[3] = {u0[1] * e[2] - u0[2] * e[1], u0[2] * e[0] - u0[0] * e[2], u0[0] * e[1] - u0[1] * e[0]};
  const FSR_T nc = sqrt(c1[0] * c1[0] + c1[1] * c1[1] + c1[2] * c1[2]);
  FSR_UNROLL for (int k = 0; k < 3; ++k) u1[k] = FSR_IF(rank1, c1[k] / nc, u1[k] / n1);
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
FSR_FN void FSR(jfloor)(FSR_T J, fsr_real c, FSR_T* h, FSR_T* dh, FSR_T* ddh) {
  const FSR_M above = J >= c;
  // The exponent is clamped at 0 so the unused side stays finite.
  const FSR_T e = exp(2 * FSR_IF(above, FSR_C(0), J - c) / c);
  *h = FSR_IF(above, J, (fsr_real)0.5 * c * (1 + e));
  *dh = FSR_IF(above, FSR_C(1), e);
  *ddh = FSR_IF(above, FSR_C(0), 2 * e / c);
}

// f = h^(-2/3), g = h^(-4/3) as functions of J, with first and second derivatives.
FSR_FN void FSR(dev_factors)(const fsr_material* m, FSR_T J, FSR_T* f, FSR_T* g) {
  FSR_T h, dh, ddh;
  FSR(jfloor)(J, m->j_min, &h, &dh, &ddh);
  const FSR_T cb = cbrt(h);
  f[0] = 1 / (cb * cb);
  g[0] = f[0] * f[0];
  f[1] = -(fsr_real)2 / 3 * f[0] / h * dh;
  g[1] = -(fsr_real)4 / 3 * g[0] / h * dh;
  f[2] = (fsr_real)10 / 9 * f[0] / (h * h) * dh * dh - (fsr_real)2 / 3 * f[0] / h * ddh;
  g[2] = (fsr_real)28 / 9 * g[0] / (h * h) * dh * dh - (fsr_real)4 / 3 * g[0] / h * ddh;
}

// Isotropic energy density from the invariants of F (no SVD needed).
FSR_FN FSR_T FSR(iso_energy_F)(const fsr_material* m, const FSR_T* F) {
  FSR_T C[9];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) C[3 * i + j] = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
  const FSR_T I1 = C[0] + C[4] + C[8];
  FSR_T trC2 = FSR_C(0);
  FSR_UNROLL for (int i = 0; i < 9; ++i) trC2 += C[i] * C[i];
  const FSR_T I2 = (fsr_real)0.5 * (I1 * I1 - trC2);
  const FSR_T J = FSR(det3)(F);
  FSR_T f[3], g[3];
  FSR(dev_factors)(m, J, f, g);
  return m->mu10 * (f[0] * I1 - 3) + m->mu01 * (g[0] * I2 - 3) + (fsr_real)0.5 * m->kappa * (J - 1) * (J - 1);
}

// Isotropic part on the diagonal: P̂ = ∂Ψ/∂σ, H = ∂²Ψ/∂σ², and for the pairs
// (0,1), (0,2), (1,2) the eigenvalues of the 2x2 shear blocks:
// lam[2p] = (P̂i − P̂j)/(σi − σj), lam[2p+1] = (P̂i + P̂j)/(σi + σj), in closed
// form so that repeated or opposite singular values need no special case.
FSR_FN void FSR(iso_diag)(const fsr_material* m, const FSR_T* s, FSR_T* P, FSR_T* H, FSR_T* lam) {
  const FSR_T J = s[0] * s[1] * s[2];
  const FSR_T s2[3] = {s[0] * s[0], s[1] * s[1], s[2] * s[2]};
  const FSR_T S = s2[0] + s2[1] + s2[2];
  const FSR_T I1 = S;
  const FSR_T I2 = s2[0] * s2[1] + s2[0] * s2[2] + s2[1] * s2[2];
  FSR_T f[3], g[3];
  FSR(dev_factors)(m, J, f, g);
  const FSR_T Jd[3] = {s[1] * s[2], s[0] * s[2], s[0] * s[1]};
  FSR_T I2d[3];
  FSR_UNROLL for (int i = 0; i < 3; ++i) I2d[i] = 2 * s[i] * (S - s2[i]);
  const FSR_T A = m->mu10 * f[1] * I1 + m->mu01 * g[1] * I2 + m->kappa * (J - 1);
  FSR_UNROLL for (int i = 0; i < 3; ++i) P[i] = A * Jd[i] + 2 * m->mu10 * f[0] * s[i] + m->mu01 * g[0] * I2d[i];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) {
      const FSR_T Jij = i == j ? FSR_C(0) : s[3 - i - j];
      const FSR_T I1ij = FSR_C(i == j ? 2 : 0);
      const FSR_T I2ij = i == j ? 2 * (S - s2[i]) : 4 * s[i] * s[j];
      const FSR_T I1i = 2 * s[i], I1j = 2 * s[j];
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
FSR_FN FSR_T FSR(active_curve)(FSR_T l, FSR_T* f, FSR_T* df) {
  const fsr_real a = (fsr_real)64 / 9, lo = (fsr_real)0.375, hi = (fsr_real)1.625, c = (fsr_real)0.225;
  // Antiderivative measured from lo; its value at 1 is subtracted at the end.
  const fsr_real F06 = (fsr_real)0.027, F14 = (fsr_real)0.027 + (fsr_real)0.8 - (fsr_real)4 / 3 * (fsr_real)0.128;
  const fsr_real F1 = (fsr_real)0.027 + (fsr_real)0.4 - (fsr_real)4 / 3 * (fsr_real)0.064;
  // Pieces from the right; each test overrides the ones beyond it.
  FSR_T fv = FSR_C(0), dfv = FSR_C(0), Fl = FSR_C(F14 + a / 3 * c * c * c);
  const FSR_M in3 = l <= hi, in2 = l <= (fsr_real)1.4, in1 = l <= (fsr_real)0.6, in0 = l <= lo;
  const FSR_T y = l - hi;
  fv = FSR_IF(in3, a * y * y, fv);
  dfv = FSR_IF(in3, 2 * a * y, dfv);
  Fl = FSR_IF(in3, F14 + a / 3 * (y * y * y + c * c * c), Fl);
  const FSR_T x = l - 1;
  fv = FSR_IF(in2, 1 - 4 * x * x, fv);
  dfv = FSR_IF(in2, -8 * x, dfv);
  Fl = FSR_IF(in2, F06 + (l - (fsr_real)0.6) - (fsr_real)4 / 3 * (x * x * x + (fsr_real)0.064), Fl);
  const FSR_T z = l - lo;
  fv = FSR_IF(in1, a * z * z, fv);
  dfv = FSR_IF(in1, 2 * a * z, dfv);
  Fl = FSR_IF(in1, a / 3 * z * z * z, Fl);
  *f = FSR_IF(in0, FSR_C(0), fv);
  *df = FSR_IF(in0, FSR_C(0), dfv);
  return FSR_IF(in0, FSR_C(0), Fl) - F1;
}

// Passive fibre stiffening: f = p1 (exp(p2 x) − 1 − p2 x), x = λ − 1 > 0,
// continued linearly beyond stretch_lin. Returns the integral from 1 to λ.
FSR_FN FSR_T FSR(passive_curve)(const fsr_material* m, FSR_T l, FSR_T* f, FSR_T* df) {
  const fsr_real xs = m->stretch_lin - 1;
  const FSR_M slack = l <= 1;
  // x is clamped at 0 below λ = 1 so the unused side stays finite.
  const FSR_T x = FSR_IF(slack, FSR_C(0), l - 1);
  const FSR_M linear = x > xs;
  const FSR_T xe = FSR_IF(linear, FSR_C(xs), x);
  const FSR_T e = exp(m->p2 * xe);
  const FSR_T fe = m->p1 * (e - 1 - m->p2 * xe);
  const FSR_T dfe = m->p1 * m->p2 * (e - 1);
  const FSR_T Fe = m->p1 * ((e - 1) / m->p2 - xe - (fsr_real)0.5 * m->p2 * xe * xe);
  const FSR_T d = x - xs;
  *f = FSR_IF(slack, FSR_C(0), FSR_IF(linear, fe + dfe * d, fe));
  *df = FSR_IF(slack, FSR_C(0), dfe);
  return FSR_IF(slack, FSR_C(0), FSR_IF(linear, Fe + fe * d + (fsr_real)0.5 * dfe * d * d, Fe));
}

// Fibre energy density φ Ψ_fibre(λ) and its first two derivatives in λ.
FSR_FN FSR_T FSR(fibre)(const fsr_material* m, FSR_T l, FSR_T alpha, FSR_T phi, FSR_T* d1, FSR_T* d2) {
  FSR_T fa, dfa, fp, dfp;
  const FSR_T Ea = FSR(active_curve)(l, &fa, &dfa);
  const FSR_T Ep = FSR(passive_curve)(m, l, &fp, &dfp);
  const FSR_T k = phi * m->sigma_max;
  *d1 = k * (alpha * fa + fp);
  *d2 = k * (alpha * dfa + dfp);
  return k * (alpha * Ea + Ep);
}

// F a and its length, the fibre stretch λ.
FSR_FN FSR_T FSR(fibre_stretch)(const FSR_T* F, const FSR_T* a, FSR_T* Fa) {
  FSR_UNROLL for (int i = 0; i < 3; ++i) Fa[i] = F[3 * i] * a[0] + F[3 * i + 1] * a[1] + F[3 * i + 2] * a[2];
  return sqrt(Fa[0] * Fa[0] + Fa[1] * Fa[1] + Fa[2] * Fa[2]);
}

// Energy density Ψ(F) of a tet with unit fibre a, muscle fraction phi and activation alpha.
FSR_FN FSR_T FSR(energy_density)(const fsr_material* m, const FSR_T* F, const FSR_T* a, FSR_T phi, FSR_T alpha) {
  FSR_T Fa[3], d1, d2;
  const FSR_T l = FSR(fibre_stretch)(F, a, Fa);
  const FSR_T fibre = FSR(fibre)(m, l, alpha, phi, &d1, &d2);
  return FSR(iso_energy_F)(m, F) + FSR_IF(phi > 0, fibre, FSR_C(0));
}

// First Piola-Kirchhoff stress P = ∂Ψ/∂F, from the invariants like the
// energy: with ∂I1/∂F = 2F, ∂I2/∂F = 2(I1 F − F C) and ∂J/∂F = cof F (valid
// for inverted tets too),
//   P = A cof F + 2 μ10 f F + 2 μ01 g (I1 F − F C),  A = μ10 f' I1 + μ01 g' I2 + κ (J − 1),
// the same function as U P̂(σ) Vᵀ from iso_diag (tested) without the SVD,
// which took 85 % of the gradient kernel. Only the stiffness needs the
// diagonal frame (for the definiteness fix).
FSR_FN void FSR(stress)(const fsr_material* m, const FSR_T* F, const FSR_T* a, FSR_T phi, FSR_T alpha, FSR_T* P) {
  FSR_T C[9], FC[9], cof[9];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) C[3 * i + j] = F[i] * F[j] + F[3 + i] * F[3 + j] + F[6 + i] * F[6 + j];
  FSR(mat3_mul)(F, C, FC);
  const FSR_T I1 = C[0] + C[4] + C[8];
  FSR_T trC2 = FSR_C(0);
  FSR_UNROLL for (int i = 0; i < 9; ++i) trC2 += C[i] * C[i];
  const FSR_T I2 = (fsr_real)0.5 * (I1 * I1 - trC2);
  cof[0] = F[4] * F[8] - F[5] * F[7];
  cof[1] = F[5] * F[6] - F[3] * F[8];
  cof[2] = F[3] * F[7] - F[4] * F[6];
  cof[3] = F[2] * F[7] - F[1] * F[8];
  cof[4] = F[0] * F[8] - F[2] * F[6];
  cof[5] = F[1] * F[6] - F[0] * F[7];
  cof[6] = F[1] * F[5] - F[2] * F[4];
  cof[7] = F[2] * F[3] - F[0] * F[5];
  cof[8] = F[0] * F[4] - F[1] * F[3];
  const FSR_T J = F[0] * cof[0] + F[1] * cof[1] + F[2] * cof[2];
  FSR_T f[3], g[3];
  FSR(dev_factors)(m, J, f, g);
  const FSR_T A = m->mu10 * f[1] * I1 + m->mu01 * g[1] * I2 + m->kappa * (J - 1);
  const FSR_T bF = 2 * m->mu10 * f[0] + 2 * m->mu01 * g[0] * I1, bFC = 2 * m->mu01 * g[0];
  FSR_UNROLL for (int k = 0; k < 9; ++k) P[k] = A * cof[k] + bF * F[k] - bFC * FC[k];
  FSR_T Fa[3], d1, d2;
  const FSR_T l = FSR(fibre_stretch)(F, a, Fa);
  const FSR_M on = phi > 0 && l > (fsr_real)1e-12;
  const FSR_T ls = FSR_IF(on, l, FSR_C(1));
  FSR(fibre)(m, ls, alpha, phi, &d1, &d2);
  const FSR_T w = FSR_IF(on, d1 / ls, FSR_C(0));
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) P[3 * i + j] += w * Fa[i] * a[j];
}

// Projects a symmetric 3x3 onto the PSD cone (negative eigenvalues → 0).
// A positive definite H (leading minors > 0: the usual case away from
// inversion) is returned unchanged, without the eigen-decomposition.
FSR_FN void FSR(psd3)(FSR_T* H) {
  const FSR_M pd = H[0] > 0 && H[0] * H[4] - H[1] * H[3] > 0 && FSR(det3)(H) > 0;
  if (FSR_ALL(pd)) return;
  FSR_T A[9], Q[9], w[3];
  FSR_UNROLL for (int i = 0; i < 9; ++i) A[i] = H[i];
  FSR(sym_eig3)(A, Q, w);
  FSR_UNROLL for (int k = 0; k < 3; ++k) w[k] = FSR_IF(w[k] > 0, w[k], FSR_C(0));
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j)
      H[3 * i + j] = FSR_IF(pd, H[3 * i + j],
                            Q[3 * i] * w[0] * Q[3 * j] + Q[3 * i + 1] * w[1] * Q[3 * j + 1] +
                                Q[3 * i + 2] * w[2] * Q[3 * j + 2]);
}

// dP/dF as a 9x9 matrix: δP[r] = Σ_c C[9r + c] δF[c], with r, c = 3i + j.
// fix != 0 applies the definiteness fix, making C symmetric PSD.
FSR_FN void FSR(stress_derivative)(const fsr_material* m, const FSR_T* F, const FSR_T* a, FSR_T phi, FSR_T alpha,
                                   int fix, FSR_T* C) {
  FSR_T U[9], s[3], V[9], Ph[3], H[9], lam[6];
  FSR(svd3)(F, U, s, V);
  FSR(iso_diag)(m, s, Ph, H, lam);
  if (fix) {
    FSR(psd3)(H);
    FSR_UNROLL for (int k = 0; k < 6; ++k) lam[k] = FSR_IF(lam[k] > 0, lam[k], FSR_C(0));
  }
  FSR_UNROLL for (int cd = 0; cd < 9; ++cd) {
    const int c = cd / 3, d = cd % 3;
    // δF = e_c e_dᵀ seen in the diagonal frame: δF̂ = Uᵀ δF V.
    FSR_T dFh[9], dPh[9];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int j = 0; j < 3; ++j) dFh[3 * i + j] = U[3 * c + i] * V[3 * d + j];
    FSR_UNROLL for (int i = 0; i < 3; ++i) dPh[4 * i] = H[3 * i] * dFh[0] + H[3 * i + 1] * dFh[4] + H[3 * i + 2] * dFh[8];
    FSR_UNROLL for (int p = 0; p < 3; ++p) {
      const int i = p == 2 ? 1 : 0, j = p == 0 ? 1 : 2;
      const FSR_T ab = (fsr_real)0.5 * (lam[2 * p] + lam[2 * p + 1]);
      const FSR_T bb = (fsr_real)0.5 * (lam[2 * p] - lam[2 * p + 1]);
      dPh[3 * i + j] = ab * dFh[3 * i + j] + bb * dFh[3 * j + i];
      dPh[3 * j + i] = bb * dFh[3 * i + j] + ab * dFh[3 * j + i];
    }
    // δP = U δP̂ Vᵀ
    FSR_T T[9];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int j = 0; j < 3; ++j) T[3 * i + j] = U[3 * i] * dPh[j] + U[3 * i + 1] * dPh[3 + j] + U[3 * i + 2] * dPh[6 + j];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int j = 0; j < 3; ++j)
        C[9 * (3 * i + j) + cd] = T[3 * i] * V[3 * j] + T[3 * i + 1] * V[3 * j + 1] + T[3 * i + 2] * V[3 * j + 2];
  }
  FSR_T Fa[3], d1, d2;
  const FSR_T l = FSR(fibre_stretch)(F, a, Fa);
  const FSR_M on = phi > 0 && l > (fsr_real)1e-12;
  const FSR_T ls = FSR_IF(on, l, FSR_C(1));
  FSR(fibre)(m, ls, alpha, phi, &d1, &d2);
  FSR_T along = FSR_IF(on, d2, FSR_C(0)), across = FSR_IF(on, d1 / ls, FSR_C(0));
  if (fix) {
    along = FSR_IF(along > 0, along, FSR_C(0));
    across = FSR_IF(across > 0, across, FSR_C(0));
  }
  const FSR_T dv[3] = {Fa[0] / ls, Fa[1] / ls, Fa[2] / ls};
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j)
      FSR_UNROLL for (int k = 0; k < 3; ++k)
        FSR_UNROLL for (int q = 0; q < 3; ++q)
          C[9 * (3 * i + j) + 3 * k + q] +=
              (along * dv[i] * dv[k] + across * ((i == k ? 1 : 0) - dv[i] * dv[k])) * a[j] * a[q];
}

// F = Ds Dm⁻¹ for corner positions x[12] (corner-major).
FSR_FN void FSR(tet_F)(const FSR_T* x, const FSR_T* Dminv, FSR_T* F) {
  FSR_T Ds[9];
  FSR_UNROLL for (int i = 0; i < 3; ++i)
    FSR_UNROLL for (int j = 0; j < 3; ++j) Ds[3 * i + j] = x[3 * (j + 1) + i] - x[i];
  FSR(mat3_mul)(Ds, Dminv, F);
}

// Energy gradient of a tet at its corners, g[12] = vol · ∂Ψ/∂x, from the
// matrix G = vol · P Dm⁻ᵀ (gradient of corners 1..3; corner 0 balances them).
// Used for forces (−g) and, with δP, for stiffness products.
FSR_FN void FSR(tet_scatter)(const FSR_T* P, const FSR_T* Dminv, FSR_T vol, FSR_T* g) {
  FSR_UNROLL for (int i = 0; i < 3; ++i) {
    FSR_T sum = FSR_C(0);
    FSR_UNROLL for (int c = 0; c < 3; ++c) {
      const FSR_T v = vol * (P[3 * i] * Dminv[3 * c] + P[3 * i + 1] * Dminv[3 * c + 1] + P[3 * i + 2] * Dminv[3 * c + 2]);
      g[3 * (c + 1) + i] = v;
      sum += v;
    }
    g[i] = -sum;
  }
}

// y[12] = K dx for the tet's stiffness K = vol · Bᵀ C B (B: corners → F).
FSR_FN void FSR(tet_stiffness_product)(const FSR_T* C, const FSR_T* Dminv, FSR_T vol, const FSR_T* dx, FSR_T* y) {
  FSR_T dF[9], dP[9];
  FSR(tet_F)(dx, Dminv, dF);
  FSR_UNROLL for (int r = 0; r < 9; ++r) {
    FSR_T sum = FSR_C(0);
    FSR_UNROLL for (int c = 0; c < 9; ++c) sum += C[9 * r + c] * dF[c];
    dP[r] = sum;
  }
  FSR(tet_scatter)(dP, Dminv, vol, y);
}

// The four 3x3 diagonal blocks of K (corner-major, D[9k + 3i + j]), for the
// block-Jacobi preconditioner.
FSR_FN void FSR(tet_diag_blocks)(const FSR_T* C, const FSR_T* Dminv, FSR_T vol, FSR_T* D) {
  // B for corner k maps δx_k (3) to δF: δF[3i + j] = δx_k[i] · b_k[j], with
  // b_k = row k−1 of Dm⁻¹ for k ≥ 1 and b_0 = −(sum of rows).
  FSR_UNROLL for (int k = 0; k < 4; ++k) {
    FSR_T b[3];
    FSR_UNROLL for (int j = 0; j < 3; ++j)
      b[j] = k == 0 ? -(Dminv[j] + Dminv[3 + j] + Dminv[6 + j]) : Dminv[3 * (k - 1) + j];
    FSR_UNROLL for (int i = 0; i < 3; ++i)
      FSR_UNROLL for (int l = 0; l < 3; ++l) {
        FSR_T sum = FSR_C(0);
        FSR_UNROLL for (int j = 0; j < 3; ++j)
          FSR_UNROLL for (int q = 0; q < 3; ++q) sum += b[j] * C[9 * (3 * i + j) + 3 * l + q] * b[q];
        D[9 * k + 3 * i + l] = vol * sum;
      }
  }
}

// The ten 3x3 blocks K_km, k ≤ m, of the tet's stiffness (the lower ones are
// their transposes), for the assembled stiffness matrix: K[9p + 3i + l] for
// pair p in the order (0,0) (0,1) (0,2) (0,3) (1,1) (1,2) (1,3) (2,2) (2,3)
// (3,3). K_km[i][l] = vol Σ_jq b_k[j] C[3i+j][3l+q] b_m[q] (b as in
// tet_diag_blocks), contracted with b_m first so that each C entry is read
// four times rather than sixteen: about 600 multiply-adds per tet.
FSR_FN void FSR(tet_blocks)(const FSR_T* C, const FSR_T* Dminv, FSR_T vol, FSR_T* K) {
  FSR_T b[4][3];
  FSR_UNROLL for (int j = 0; j < 3; ++j) {
    b[0][j] = -(Dminv[j] + Dminv[3 + j] + Dminv[6 + j]);
    b[1][j] = Dminv[j];
    b[2][j] = Dminv[3 + j];
    b[3][j] = Dminv[6 + j];
  }
  FSR_UNROLL for (int m = 0; m < 4; ++m) {
    FSR_T Cb[27];  // Cb[3(3i+j) + l] = Σ_q C[3i+j][3l+q] b_m[q]
    FSR_UNROLL for (int r = 0; r < 9; ++r)
      FSR_UNROLL for (int l = 0; l < 3; ++l)
        Cb[3 * r + l] = C[9 * r + 3 * l] * b[m][0] + C[9 * r + 3 * l + 1] * b[m][1] + C[9 * r + 3 * l + 2] * b[m][2];
    FSR_UNROLL for (int k = 0; k <= m; ++k) {
      // Pair (k, m) sits at index k·(7 − k)/2 + m in the order above.
      const int pk = k * (7 - k) / 2 + m;
      FSR_UNROLL for (int i = 0; i < 3; ++i)
        FSR_UNROLL for (int l = 0; l < 3; ++l)
          K[9 * pk + 3 * i + l] =
              vol * (b[k][0] * Cb[3 * (3 * i) + l] + b[k][1] * Cb[3 * (3 * i + 1) + l] + b[k][2] * Cb[3 * (3 * i + 2) + l]);
    }
  }
}

#undef FSR_C
