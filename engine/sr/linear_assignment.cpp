// Shortest augmenting path assignment (Jonker–Volgenant as restated for
// rectangular problems by Crouse 2016, "On implementing 2D rectangular
// assignment algorithms").
//
// Written here because no C++ library installed for this project (nor one
// packaged by Debian that we know of) solves the rectangular problem; scipy's
// linear_sum_assignment implements the same method but is Python-bound, and
// padding to a square Hungarian problem would be O(M³) on the 9k × 9k
// matrix where this costs about N augmenting searches over M columns.
//
// One row is added at a time; a Dijkstra-like search over reduced costs
// c(i,j) - u(i) - v(j) ≥ 0 finds the cheapest path from the new row to an
// unassigned column, then the duals are updated so every reduced cost stays
// non-negative and those on the assignment stay zero, which is what makes
// the final assignment optimal.
#include "sr/linear_assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace facesr {

namespace {

constexpr double kNoPath = std::numeric_limits<double>::infinity();

struct LapState {
  int rows, cols;
  const double* cost;
  std::vector<double> u, v, path_cost;
  std::vector<int32_t> path, col_of_row, row_of_col, remaining;
  std::vector<uint8_t> row_seen, col_seen;

  LapState(const double* c, int r, int n)
      : rows(r), cols(n), cost(c), u(r, 0.0), v(n, 0.0), path_cost(n), path(n, -1), col_of_row(r, -1),
        row_of_col(n, -1), remaining(n), row_seen(r), col_seen(n) {}

  // Cheapest augmenting path from `start` to a free column; returns that
  // column and the path's reduced length in `min_val`.
  int augment_path(int start, double& min_val) {
    min_val = 0;
    // Scanning the columns in reverse index order with the "prefer a free
    // column on ties" rule below keeps the result independent of anything
    // but the matrix.
    int num_remaining = cols;
    for (int it = 0; it < cols; ++it) remaining[it] = cols - 1 - it;
    std::fill(row_seen.begin(), row_seen.end(), 0);
    std::fill(col_seen.begin(), col_seen.end(), 0);
    std::fill(path_cost.begin(), path_cost.end(), kNoPath);
    int sink = -1;
    int i = start;
    while (sink < 0) {
      row_seen[i] = 1;
      const double* ci = cost + size_t(i) * size_t(cols);
      const double base = min_val - u[i];
      int best = -1;
      double lowest = kNoPath;
      for (int it = 0; it < num_remaining; ++it) {
        const int j = remaining[it];
        const double r = base + ci[j] - v[j];
        if (r < path_cost[j]) {
          path[j] = i;
          path_cost[j] = r;
        }
        if (path_cost[j] < lowest || (path_cost[j] == lowest && row_of_col[j] < 0)) {
          lowest = path_cost[j];
          best = it;
        }
      }
      require(best >= 0 && lowest < kNoPath, "linear assignment: no feasible augmenting path (non-finite costs?)");
      min_val = lowest;
      const int j = remaining[best];
      col_seen[j] = 1;
      remaining[best] = remaining[--num_remaining];
      if (row_of_col[j] < 0)
        sink = j;
      else
        i = row_of_col[j];
    }
    return sink;
  }

  void add_row(int row) {
    double min_val = 0;
    const int sink = augment_path(row, min_val);
    // Dual update: rows and columns on the search tree
    // move by how much shorter their path was than the one found.
    u[row] += min_val;
    for (int i = 0; i < rows; ++i)
      if (row_seen[i] && i != row) u[i] += min_val - path_cost[col_of_row[i]];
    for (int j = 0; j < cols; ++j)
      if (col_seen[j]) v[j] -= min_val - path_cost[j];
    // Flip the alternating path back to the new row.
    int j = sink;
    for (;;) {
      const int i = path[j];
      row_of_col[j] = i;
      std::swap(col_of_row[i], j);
      if (i == row) break;
    }
  }
};

}  // namespace

std::vector<int32_t> linear_assignment(const double* cost, int rows, int cols, double* total) {
  require(rows >= 0 && cols >= 0, "linear assignment: negative matrix size");
  require(rows <= cols, "linear assignment: " + std::to_string(rows) + " rows > " + std::to_string(cols) +
                            " columns; use linear_assignment_any");
  require(rows == 0 || cost != nullptr, "linear assignment: null cost matrix");
  const size_t n = size_t(rows) * size_t(cols);
  for (size_t k = 0; k < n; ++k)
    require(std::isfinite(cost[k]), "linear assignment: cost(" + std::to_string(k / size_t(cols)) + ", " +
                                        std::to_string(k % size_t(cols)) + ") is not finite");
  LapState s(cost, rows, cols);
  for (int r = 0; r < rows; ++r) s.add_row(r);
  if (total) {
    double sum = 0;
    for (int r = 0; r < rows; ++r) sum += cost[size_t(r) * size_t(cols) + size_t(s.col_of_row[r])];
    *total = sum;
  }
  return std::move(s.col_of_row);
}

std::vector<int32_t> linear_assignment_any(const double* cost, int rows, int cols, double* total) {
  if (rows <= cols) return linear_assignment(cost, rows, cols, total);
  std::vector<double> t(size_t(rows) * size_t(cols));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) t[size_t(c) * size_t(rows) + size_t(r)] = cost[size_t(r) * size_t(cols) + size_t(c)];
  const std::vector<int32_t> row_of_col = linear_assignment(t.data(), cols, rows, total);
  std::vector<int32_t> col_of_row(size_t(rows), -1);
  for (int c = 0; c < cols; ++c) col_of_row[size_t(row_of_col[size_t(c)])] = c;
  return col_of_row;
}

}  // namespace facesr
