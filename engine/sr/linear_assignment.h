#pragma once
// Minimum-cost rectangular linear assignment (paper §3.2 maps the LR nodes
// one-to-one onto HR surface vertices with it, citing Crouse 2016).
#include <cstdint>
#include <vector>

namespace facesr {

// cost: rows × cols, row-major, finite. Requires rows <= cols. Returns for
// every row a distinct column such that the summed cost is least; `total`
// (if given) receives that sum. Ties are broken deterministically.
std::vector<int32_t> linear_assignment(const double* cost, int rows, int cols, double* total = nullptr);

// Any shape: when rows > cols, every column gets a distinct row and the rows
// left over are -1 (solved on the transposed matrix).
std::vector<int32_t> linear_assignment_any(const double* cost, int rows, int cols, double* total = nullptr);

}  // namespace facesr
