#pragma once
#include <vector>

namespace facesr {

// Descriptive statistics of a set of errors (cm, or whatever unit the values
// carry). `std` is the population standard deviation (divided by n, not
// n - 1): the sets summarised here are whole test sets, not samples of one.
struct ErrorStats {
  double mean = 0, median = 0, std = 0, max = 0, min = 0;
  long count = 0;
};

// Throws Error when `values` is empty or holds a non-finite value. The median
// of an even count is the mean of the two middle values.
ErrorStats error_stats(std::vector<double> values);

// The same statistics with every field divided by `scale` (> 0); count kept.
ErrorStats scaled(const ErrorStats& s, double scale);

}  // namespace facesr
