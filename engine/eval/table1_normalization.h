#pragma once
#include <vector>

#include "eval/error_stats.h"

// Paper table 1: "normalized mean, median, standard deviation, and min/max"
// of the surface reconstruction errors. The table's largest entry is exactly
// 1.00 (the beta-VAE's max), so its values are statistics over the test frames
// of each method's frame-wise mean error (the fig. 5 curves), all divided by
// one common normaliser: the largest frame-wise mean error of any method on
// any test frame. Dividing every method by the same number keeps the table's
// columns comparable with each other; a ratio of two entries is the ratio of
// the errors in cm.
namespace facesr {

// frame_means[m][f]: frame-wise mean error (cm) of method m on test frame f.
// The common normaliser: max over m and f. Throws Error when there is no
// method, a method has no frames, or a value is negative or not finite.
double table1_normalizer(const std::vector<std::vector<double>>& frame_means);

// Per method, error_stats() of its frame-wise means divided by
// table1_normalizer(). When every error is 0 (all methods exact) the
// normaliser is 0 and the statistics are returned unscaled (all 0).
std::vector<ErrorStats> table1_normalized_stats(const std::vector<std::vector<double>>& frame_means);

}  // namespace facesr
