#include "sr/positional_encoding.h"

#include <cmath>

#include "core/error.h"

namespace facesr {

std::vector<float> positional_encoding(int num_nodes, int dim) { return positional_encoding(num_nodes, dim, {}); }

std::vector<float> positional_encoding(int num_nodes, int dim, const std::vector<int32_t>& rows) {
  require(num_nodes >= 0 && dim >= 0 && dim % 2 == 0,
          "positional encoding: needs num_nodes >= 0 and an even dim >= 0 (got " + std::to_string(num_nodes) + ", " +
              std::to_string(dim) + ")");
  require(rows.empty() || rows.size() == size_t(num_nodes),
          "positional encoding: " + std::to_string(rows.size()) + " rows for " + std::to_string(num_nodes) + " nodes");
  std::vector<float> pe(size_t(num_nodes) * size_t(dim));
  for (int i = 0; i < num_nodes; ++i) {
    const int32_t row = rows.empty() ? i : rows[size_t(i)];
    require(row >= 0, "positional encoding: row " + std::to_string(row) + " of node " + std::to_string(i) + " is negative");
    for (int m = 0; m < dim / 2; ++m) {
      // In double: i reaches thousands, and float sin of large arguments loses digits.
      const double a = double(row) / std::pow(10000.0, 2.0 * m / dim);
      pe[size_t(i) * dim + 2 * m] = float(std::sin(a));
      pe[size_t(i) * dim + 2 * m + 1] = float(std::cos(a));
    }
  }
  return pe;
}

}  // namespace facesr
