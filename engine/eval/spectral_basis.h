#pragma once
#include <Eigen/Core>
#include <string>

#include "core/types.h"

// The low-frequency basis of the thesis's spectral partition (§4.2.1, §4.4.1):
// the first k eigenvectors U_(k) of the generalised problem
//   L phi = lambda M phi        (eq. 4.2: L = U Lambda U^T M, U^T M U = I)
// with L the cotangent Laplacian (cotan_laplacian.h, eq. 4.10) and M the mixed
// Voronoi mass matrix (voronoi_mass.h) of the rest surface. It depends only on
// the rest surface, so it is computed once per rig and shared by every frame
// and every method.
namespace facesr {

struct SpectralOptions {
  // Size of the low band. 100 by default: the 100th eigenfunction's
  // wavelength (cutoff_wavelength_cm) is 5.5 cm on the ICT face (837 cm^2)
  // and 3.8 cm on the procedural one (370 cm^2), so the low band holds the
  // error of the overall shape (jaw, cheeks, brows out of place) and the high
  // band wrinkles, lip and lid detail: the split the paper's fig. 6 argues
  // over. The thesis splits at k = 500-1200 on 11-26k vertex heads for mesh
  // synthesis, where the low band must rebuild the whole shape; an error
  // split needs fewer, and k = 100 solves in about 1 s on the ICT face
  // (k = 200: 3.5 s; the cost grows faster than k).
  int k = 100;
  // Solve densely (all eigenvectors) instead of by shift-invert Lanczos; for
  // small meshes and for checking the iterative solve.
  bool dense = false;
};

struct SpectralBasis {
  int k = 0;
  Eigen::VectorXd eigenvalues;  // k, ascending, 1/cm^2 (0 once per connected component)
  Eigen::MatrixXd vectors;      // M x k, M-orthonormal: vectors^T diag(mass) vectors = I
  Eigen::VectorXd mass;         // M, mixed Voronoi areas (cm^2); 0 on vertices in no triangle
  double area_cm2 = 0;          // surface area = sum of mass
  int components = 0;           // connected components of the surface
  long active_vertices = 0;     // vertices with mass > 0 (the others are outside the basis)
  double seconds = 0;           // assembly + eigen solve wall time
  std::string solver;           // "shift-invert Lanczos (Spectra)" or "dense"

  long num_vertices() const { return long(mass.size()); }
  // 2 pi / sqrt(lambda_k): the shortest wavelength (cm) the low band holds
  // (0 when lambda_k is 0).
  double cutoff_wavelength_cm() const;
};

// Throws Error when the surface has no non-degenerate triangle, k is not in
// [1, active vertices - 1], or the eigen solve does not converge.
SpectralBasis spectral_basis(const Points& V, const Tris& F, const SpectralOptions& opt = {});

}  // namespace facesr
