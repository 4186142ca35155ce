#pragma once
#include <vector>

namespace facesr {

// The sine/cosine positional encoding of Transformers (Vaswani et al. 2017)
// over the LR node index, which the paper concatenates to each node's
// displacement (§3.1): row i, columns 2m and 2m+1 are sin and cos of
// i / 10000^(2m / dim). Returns num_nodes × dim floats, row-major; dim even.
std::vector<float> positional_encoding(int num_nodes, int dim);

}  // namespace facesr
