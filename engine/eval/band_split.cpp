#include "eval/band_split.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace facesr {
namespace {

void check(const SpectralBasis& basis, const Points& e, const char* who) {
  require(basis.k > 0 && basis.vectors.cols() == basis.k && basis.vectors.rows() == basis.mass.size(),
          std::string(who) + ": the spectral basis is empty or inconsistent");
  require(e.rows() == basis.mass.size(), std::string(who) + ": the field has " + std::to_string(e.rows()) +
                                             " vertices, the basis " + std::to_string(basis.mass.size()));
  require(e.allFinite(), std::string(who) + ": the field has a non-finite value");
}

void finish(BandSplit& s, double area) {
  const double total = s.low_energy + s.high_energy;
  s.low_fraction = total > 0 ? s.low_energy / total : 0;
  s.high_fraction = total > 0 ? s.high_energy / total : 0;
  s.low_rms_cm = area > 0 ? std::sqrt(s.low_energy / area) : 0;
  s.high_rms_cm = area > 0 ? std::sqrt(s.high_energy / area) : 0;
}

}  // namespace

BandSplit band_split(const SpectralBasis& basis, const Points& e) {
  check(basis, e, "band split");
  const Eigen::MatrixXd Me = basis.mass.asDiagonal() * e;
  const Eigen::MatrixXd coeff = basis.vectors.transpose() * Me;  // k x 3
  BandSplit s;
  const double total = (e.array() * Me.array()).sum();
  s.low_energy = std::min(coeff.squaredNorm(), total);
  // The rest by subtraction: with an M-orthonormal basis |e_high|_M^2 =
  // |e|_M^2 - |c|^2, exact up to rounding, which the clamp absorbs.
  s.high_energy = std::max(0.0, total - s.low_energy);
  finish(s, basis.area_cm2);
  return s;
}

Points low_band(const SpectralBasis& basis, const Points& e) {
  check(basis, e, "low band");
  const Eigen::MatrixXd coeff = basis.vectors.transpose() * (basis.mass.asDiagonal() * e);
  return Points(basis.vectors * coeff);
}

BandSplit accumulate(const std::vector<BandSplit>& splits, double area_cm2) {
  BandSplit s;
  for (const BandSplit& x : splits) {
    s.low_energy += x.low_energy;
    s.high_energy += x.high_energy;
  }
  finish(s, splits.empty() ? 0 : area_cm2 * double(splits.size()));
  return s;
}

}  // namespace facesr
