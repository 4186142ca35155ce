#pragma once
#include <Eigen/SparseCore>

#include "core/types.h"

namespace facesr {

// Cotangent Laplacian of a triangle surface, the thesis's eq. (4.10) up to
// sign and a factor 1/2:
//   L_ij = -(cot alpha_ij + cot beta_ij) / 2   for an edge ij,
//   L_ii = -sum_{j != i} L_ij,
// with alpha_ij, beta_ij the angles opposite the edge in its (one or two)
// triangles. The sign makes L positive semi-definite, so "the k smallest
// eigenvalues" of L phi = lambda M phi are the k lowest frequencies; with the
// 1/2 and the Voronoi mass matrix M (voronoi_mass.h), M^-1 L approximates
// -Delta, so lambda is in 1/cm^2 and 2 pi / sqrt(lambda) is a wavelength in cm.
// Neither change alters the eigenvectors. L is symmetric and L 1 = 0 on every
// connected component; border edges have a single cotangent (the natural,
// Neumann, boundary condition). Degenerate (zero-area) triangles are skipped:
// their cotangents are unbounded and they cover no surface.
// Throws Error when a triangle refers to a vertex outside V.
Eigen::SparseMatrix<double> cotan_laplacian(const Points& V, const Tris& F);

// Whether triangle f of (V, F) is degenerate in the sense used above and by
// voronoi_mass(): its doubled area is below 1e-12 of its squared edge lengths.
bool degenerate_triangle(const Points& V, const Tris& F, int f);

}  // namespace facesr
