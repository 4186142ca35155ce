#pragma once
#include <cstdint>
#include <vector>

namespace facesr {

// The sine/cosine positional encoding of Transformers (Vaswani et al. 2017)
// over the LR node index, which the paper concatenates to each node's
// displacement (§3.1): row i, columns 2m and 2m+1 are sin and cos of
// i / 10000^(2m / dim). Returns num_nodes × dim floats, row-major; dim even.
std::vector<float> positional_encoding(int num_nodes, int dim);

// The same with node n taking the encoding of index rows[n] instead of n
// (rows.size() nodes; every row >= 0). A model carried over to another rig
// keeps the encoding each of its nodes was trained with by giving each new
// node the row of the old node it corresponds to (sr/model_transfer.h).
// Empty rows: the plain encoding of num_nodes nodes.
std::vector<float> positional_encoding(int num_nodes, int dim, const std::vector<int32_t>& rows);

}  // namespace facesr
