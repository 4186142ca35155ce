#pragma once
#include "eval/spectral_basis.h"

// How much of an error field is low and how much high frequency (thesis
// §4.3-4.4.1). The low band of a field e (M x 3, e.g. prediction - reference
// displacement) is its M-orthogonal projection onto the basis, eq. (4.4)/(4.11):
//   e_low = U_(k) U_(k)^T M e,      e_high = e - e_low = (I - X) e.
// The two bands are M-orthogonal, so the squared M-norm |e|_M^2 = sum_c
// e_c^T M e_c (an area integral of |e|^2, cm^2 x cm^2) splits exactly into the
// bands' shares, and the fractions sum to 1.
namespace facesr {

struct BandSplit {
  double low_energy = 0, high_energy = 0;      // squared M-norms, cm^4 (area x length^2)
  double low_fraction = 0, high_fraction = 0;  // shares of the total; both 0 when e = 0
  double low_rms_cm = 0, high_rms_cm = 0;      // sqrt(energy / area): area-weighted RMS of each band
  double total_energy() const { return low_energy + high_energy; }
};

// e: M x 3 (cm) over the basis's vertices. Vertices outside the basis (mass 0)
// carry no weight. Throws Error when the row count differs from the basis's
// or a value is not finite.
BandSplit band_split(const SpectralBasis& basis, const Points& e);

// The low band itself, U_(k) U_(k)^T M e (M x 3, cm); e - low_band() is the high band.
Points low_band(const SpectralBasis& basis, const Points& e);

// Sums the energies of several splits (e.g. the frames of a test set) and
// recomputes fractions and RMS over all of them: frames with more error weigh
// more, as they do in the per-vertex statistics.
BandSplit accumulate(const std::vector<BandSplit>& splits, double area_cm2);

}  // namespace facesr
