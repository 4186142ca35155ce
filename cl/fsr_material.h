// Teran muscle material, shared verbatim by the OpenCL kernels (cl/sim.cl)
// and the C++ CPU reference (engine/sim). One source for the formulas is what
// makes the OpenCL/CPU parity tests meaningful.
//
// Written in the common subset of C99 and OpenCL C 1.2: plain functions on
// private arrays, 3x3 matrices row-major (M[3*i+j]), no address-space
// qualifiers. Units: lengths cm, stresses kPa, energies kPa·cm³ (mJ). The
// functions themselves are in fsr_material_body.h, written once for any value
// type: this file instantiates them for scalars (fsr_svd3, fsr_stress, ...),
// and cl/sim.cl again for vectors of tets (fsr8_...), which is how the CPU
// devices run eight tets per SIMD instruction.
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


// The scalar instantiation: fsr_svd3, fsr_stress, ... (one tet per call).
#define FSR_T fsr_real
#define FSR(name) fsr_##name
#define FSR_IF(c, a, b) ((c) ? (a) : (b))
#define FSR_ALL(c) (c)
#ifdef __OPENCL_VERSION__
#define FSR_M int
#else
#define FSR_M bool
#endif
#include "fsr_material_body.h"
#undef FSR_T
#undef FSR
#undef FSR_IF
#undef FSR_ALL
#undef FSR_M

#endif  // FSR_MATERIAL_H
