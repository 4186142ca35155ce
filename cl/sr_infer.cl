// Super-resolution inference kernels (engine/runtime/cl_inference.cpp): the
// paper's network (§3) for one frame, in float. Feature matrices are
// row-major with an explicit row stride and column offset, so the encoder's
// submodules write their outputs side by side into one N × C buffer that is
// the encoded feature [x0, z1, ..., zS] without any copy.
//
// Launches are 1D; the tiled kernels map a 1D work-group of TILE*TILE items
// onto a TILE × TILE tile.

#define TILE 16

// x0 = [displacement / input_scale, positional encoding].
__kernel void sr_input(const uint N, const uint pe_dim, const float inv_scale, __global const float* disp,
                       __global const float* pe, __global float* enc, const uint enc_stride) {
  const uint i = get_global_id(0);
  if (i >= N) return;
  __global float* row = enc + (size_t)i * enc_stride;
  for (uint c = 0; c < 3; ++c) row[c] = disp[3 * i + c] * inv_scale;
  for (uint c = 0; c < pe_dim; ++c) row[3 + c] = pe[(size_t)i * pe_dim + c];
}

// out[r, o] = act(Σ_k A[r, k] · W[o, k] + bias[o]) over two inputs side by
// side: k < K1 reads a1, k ≥ K1 reads a2 (K2 = 0 for one input); offsets are
// in elements (column offsets within a wider feature matrix). in_sine
// applies sin(omega0 · a) to every input value (SIREN layers); out_leaky
// applies LeakyReLU(slope) to the result. W is out_dim × (K1 + K2).
// Tiles of A and W are staged in local memory.
__kernel void dense(const uint rows, const uint out_dim, const uint K1, const uint K2, __global const float* a1,
                    const uint s1, const uint off1, __global const float* a2, const uint s2, const uint off2,
                    __global const float* W, __global const float* bias, __global float* out,
                    const uint out_stride, const uint out_off, const int in_sine, const float omega0,
                    const int out_leaky, const float slope) {
  a1 += off1;
  a2 += off2;
  out += out_off;
  __local float As[TILE][TILE + 1];
  __local float Ws[TILE][TILE + 1];
  const uint lid = get_local_id(0), ly = lid / TILE, lx = lid % TILE;
  const uint tiles_x = (out_dim + TILE - 1) / TILE;
  const uint group = get_group_id(0);
  const uint r0 = (group / tiles_x) * TILE, o0 = (group % tiles_x) * TILE;
  const uint r = r0 + ly, o = o0 + lx;
  const uint K = K1 + K2;
  float acc = 0.0f;
  for (uint k0 = 0; k0 < K; k0 += TILE) {
    // A tile: row r0 + ly, column k0 + lx. W tile: output o0 + ly, column k0 + lx.
    const uint ka = k0 + lx;
    float av = 0.0f;
    if (r0 + ly < rows && ka < K) {
      av = ka < K1 ? a1[(size_t)(r0 + ly) * s1 + ka] : a2[(size_t)(r0 + ly) * s2 + (ka - K1)];
      if (in_sine) av = sin(omega0 * av);
    }
    As[ly][lx] = av;
    Ws[ly][lx] = (o0 + ly < out_dim && ka < K) ? W[(size_t)(o0 + ly) * K + ka] : 0.0f;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint k = 0; k < TILE; ++k) acc += As[ly][k] * Ws[lx][k];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (r < rows && o < out_dim) {
    float v = acc + bias[o];
    if (out_leaky && v < 0.0f) v *= slope;
    out[(size_t)r * out_stride + o] = v;
  }
}

// EdgeConv aggregation: y[i, c] = max_q LeakyReLU(self[i, c] + other[nbr[i, q], c]),
// where self = h (Θ1 − Θ2)ᵀ + b and other = h Θ2ᵀ (the edge product split).
__kernel void edge_max(const uint N, const uint D, const uint k, __global const float* self,
                       __global const float* other, __global const int* nbr, const float slope, __global float* y) {
  const uint id = get_global_id(0);
  if (id >= N * D) return;
  const uint i = id / D, c = id % D;
  const float s = self[(size_t)i * D + c];
  float best = -INFINITY;
  for (uint q = 0; q < k; ++q) {
    float v = s + other[(size_t)nbr[(size_t)i * k + q] * D + c];
    if (v < 0.0f) v *= slope;
    best = fmax(best, v);
  }
  y[(size_t)i * D + c] = best;
}

// Global max and mean over the nodes of each column of y (N × D):
// pooled[c] = max, pooled[D + c] = mean. One work-group per column.
__kernel void pool_columns(const uint N, const uint D, __global const float* y, __global float* pooled,
                           __local float* smax, __local float* ssum) {
  const uint c = get_group_id(0), lid = get_local_id(0), L = get_local_size(0);
  float m = -INFINITY, s = 0.0f;
  for (uint i = lid; i < N; i += L) {
    const float v = y[(size_t)i * D + c];
    m = fmax(m, v);
    s += v;
  }
  smax[lid] = m;
  ssum[lid] = s;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint h = L / 2; h > 0; h >>= 1) {
    if (lid < h) {
      smax[lid] = fmax(smax[lid], smax[lid + h]);
      ssum[lid] += ssum[lid + h];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) {
    pooled[c] = smax[0];
    pooled[D + c] = ssum[0] / (float)N;
  }
}

// The pooled features' share of the shared FC, the same for every node:
// out[o] = b[o] + Σ_c Wmax[o, c] gmax[c] + Wavg[o, c] gavg[c], with W the
// FC's full weight (D × (3D + in)) and its pooled columns at D and 2D.
__kernel void pooled_bias(const uint D, const uint in_dim, __global const float* W, __global const float* b,
                          __global const float* pooled, __global float* out) {
  const uint o = get_global_id(0);
  if (o >= D) return;
  const uint K = 3 * D + in_dim;
  float s = b[o];
  for (uint c = 0; c < D; ++c) s += W[(size_t)o * K + D + c] * pooled[c] + W[(size_t)o * K + 2 * D + c] * pooled[D + c];
  out[o] = s;
}

// Squared row norms of h (N rows of D, row stride s, first column off).
__kernel void row_sqnorm(const uint N, const uint D, __global const float* h, const uint s, const uint off,
                         __global float* sq) {
  const uint i = get_global_id(0);
  h += off;
  if (i >= N) return;
  float v = 0.0f;
  for (uint c = 0; c < D; ++c) {
    const float x = h[(size_t)i * s + c];
    v += x * x;
  }
  sq[i] = v;
}

// k nearest other rows in feature space by |a|² + |b|² − 2 a·b (the formula
// the trained network used), nearest first, ties by lower index. One work-item
// per query; candidates stream through local memory in blocks of KNN_BLOCK
// rows shared by the work-group. k ≤ KNN_MAX_K, D ≤ KNN_MAX_D.
#define KNN_BLOCK 32
#define KNN_MAX_K 16
#define KNN_MAX_D 256
__kernel void feature_knn(const uint N, const uint D, const uint k, __global const float* h, const uint s,
                          const uint off, __global const float* sq, __global int* nbr, __local float* block) {
  const uint i = get_global_id(0), lid = get_local_id(0), L = get_local_size(0);
  h += off;
  const bool active = i < N;
  float q[KNN_MAX_D];
  if (active)
    for (uint c = 0; c < D; ++c) q[c] = h[(size_t)i * s + c];
  const float sqi = active ? sq[i] : 0.0f;
  float bd[KNN_MAX_K];
  int bi[KNN_MAX_K];
  for (uint t = 0; t < k; ++t) {
    bd[t] = INFINITY;
    bi[t] = 0x7fffffff;
  }
  for (uint j0 = 0; j0 < N; j0 += KNN_BLOCK) {
    const uint nb = min((uint)KNN_BLOCK, N - j0);
    for (uint e = lid; e < nb * D; e += L) block[e] = h[(size_t)(j0 + e / D) * s + e % D];
    barrier(CLK_LOCAL_MEM_FENCE);
    if (active)
      for (uint jj = 0; jj < nb; ++jj) {
        const uint j = j0 + jj;
        if (j == i) continue;
        float dot = 0.0f;
        for (uint c = 0; c < D; ++c) dot += q[c] * block[jj * D + c];
        const float d = sqi + sq[j] - 2.0f * dot;
        if (d < bd[k - 1] || (d == bd[k - 1] && (int)j < bi[k - 1])) {
          int t = (int)k - 1;
          while (t > 0 && (d < bd[t - 1] || (d == bd[t - 1] && (int)j < bi[t - 1]))) {
            bd[t] = bd[t - 1];
            bi[t] = bi[t - 1];
            --t;
          }
          bd[t] = d;
          bi[t] = (int)j;
        }
      }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (active)
    for (uint t = 0; t < k; ++t) nbr[(size_t)i * k + t] = bi[t];
}

// Coordinate-based upsampling with the load-time weights:
// pre[j, c] = Σ_q w[j, q] · r[idx[j, q], c] (r: N × H, pre: M × H).
__kernel void upsample_features(const uint M, const uint K, const uint H, __global const float* w, __global const int* idx,
                       __global const float* r, __global float* pre) {
  const uint id = get_global_id(0);
  if (id >= M * H) return;
  const uint j = id / H, c = id % H;
  float s = 0.0f;
  for (uint q = 0; q < K; ++q) s += w[(size_t)j * K + q] * r[(size_t)idx[(size_t)j * K + q] * H + c];
  pre[id] = s;
}
