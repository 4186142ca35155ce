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
// in elements (column offsets within a wider feature matrix). act: 0 none,
// 1 LeakyReLU(slope), 2 sin(omega0 · v) (a SIREN layer's activation, applied
// where its output is made so the next layer reads it once). W is
// out_dim × (K1 + K2), row-major. Two kernels compute the same thing:
// dense_rows for CPU devices (one work-item per row; contiguous dot products
// that PoCL vectorises, four outputs per pass over the row) and dense_tiled
// for GPUs (TILE × TILE tiles staged in local memory).
#define ACTIVATE(v) (act == 1 ? ((v) < 0.0f ? slope * (v) : (v)) : act == 2 ? sin(omega0 * (v)) : (v))

__kernel void dense_rows(const uint rows, const uint out_dim, const uint K1, const uint K2, __global const float* a1,
                         const uint s1, const uint off1, __global const float* a2, const uint s2, const uint off2,
                         __global const float* W, __global const float* bias, __global float* out,
                         const uint out_stride, const uint out_off, const int act, const float omega0,
                         const float slope) {
  const uint r = get_global_id(0);
  if (r >= rows) return;
  const uint K = K1 + K2;
  __global const float* x1 = a1 + off1 + (size_t)r * s1;
  __global const float* x2 = a2 + off2 + (size_t)r * s2;
  __global float* y = out + out_off + (size_t)r * out_stride;
  uint o = 0;
  for (; o + 4 <= out_dim; o += 4) {
    __global const float* w0 = W + (size_t)o * K;
    __global const float* w1 = w0 + K;
    __global const float* w2 = w1 + K;
    __global const float* w3 = w2 + K;
    float t0 = 0.0f, t1 = 0.0f, t2 = 0.0f, t3 = 0.0f;
    for (uint k = 0; k < K1; ++k) {
      const float x = x1[k];
      t0 += x * w0[k];
      t1 += x * w1[k];
      t2 += x * w2[k];
      t3 += x * w3[k];
    }
    for (uint k = 0; k < K2; ++k) {
      const float x = x2[k];
      t0 += x * w0[K1 + k];
      t1 += x * w1[K1 + k];
      t2 += x * w2[K1 + k];
      t3 += x * w3[K1 + k];
    }
    t0 += bias[o];
    t1 += bias[o + 1];
    t2 += bias[o + 2];
    t3 += bias[o + 3];
    y[o] = ACTIVATE(t0);
    y[o + 1] = ACTIVATE(t1);
    y[o + 2] = ACTIVATE(t2);
    y[o + 3] = ACTIVATE(t3);
  }
  for (; o < out_dim; ++o) {
    __global const float* w = W + (size_t)o * K;
    float t = bias[o];
    for (uint k = 0; k < K1; ++k) t += x1[k] * w[k];
    for (uint k = 0; k < K2; ++k) t += x2[k] * w[K1 + k];
    y[o] = ACTIVATE(t);
  }
}

__kernel void dense_tiled(const uint rows, const uint out_dim, const uint K1, const uint K2, __global const float* a1,
                          const uint s1, const uint off1, __global const float* a2, const uint s2, const uint off2,
                          __global const float* W, __global const float* bias, __global float* out,
                          const uint out_stride, const uint out_off, const int act, const float omega0,
                          const float slope) {
  __local float As[TILE][TILE + 1];
  __local float Ws[TILE][TILE + 1];
  a1 += off1;
  a2 += off2;
  out += out_off;
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
    if (r0 + ly < rows && ka < K) av = ka < K1 ? a1[(size_t)(r0 + ly) * s1 + ka] : a2[(size_t)(r0 + ly) * s2 + (ka - K1)];
    As[ly][lx] = av;
    Ws[ly][lx] = (o0 + ly < out_dim && ka < K) ? W[(size_t)(o0 + ly) * K + ka] : 0.0f;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint k = 0; k < TILE; ++k) acc += As[ly][k] * Ws[lx][k];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (r < rows && o < out_dim) {
    const float v = acc + bias[o];
    out[(size_t)r * out_stride + o] = ACTIVATE(v);
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
// the trained network used), nearest first, ties by lower index. One
// work-item per query, scanning every candidate: O(N² D), the inference's
// largest cost. k ≤ KNN_MAX_K.
#define KNN_MAX_K 16

// a·b over D floats with four independent float4 partial sums: the explicit
// order lets the compiler use SIMD without fast-math reassociation (which
// would also loosen the SIREN sines elsewhere in this program).
float dot_rows(__global const float* a, __global const float* b, const uint D) {
  float4 s0 = (float4)(0.0f), s1 = (float4)(0.0f), s2 = (float4)(0.0f), s3 = (float4)(0.0f);
  uint c = 0;
  for (; c + 16 <= D; c += 16) {
    s0 += vload4(0, a + c) * vload4(0, b + c);
    s1 += vload4(0, a + c + 4) * vload4(0, b + c + 4);
    s2 += vload4(0, a + c + 8) * vload4(0, b + c + 8);
    s3 += vload4(0, a + c + 12) * vload4(0, b + c + 12);
  }
  const float4 s = (s0 + s1) + (s2 + s3);
  float t = (s.x + s.y) + (s.z + s.w);
  for (; c < D; ++c) t += a[c] * b[c];
  return t;
}

__kernel void feature_knn(const uint N, const uint D, const uint k, __global const float* h, const uint s,
                          const uint off, __global const float* sq, __global int* nbr) {
  const uint i = get_global_id(0);
  if (i >= N) return;
  h += off;
  __global const float* q = h + (size_t)i * s;
  const float sqi = sq[i];
  float bd[KNN_MAX_K];
  int bi[KNN_MAX_K];
  for (uint t = 0; t < k; ++t) {
    bd[t] = INFINITY;
    bi[t] = 0x7fffffff;
  }
  for (uint j = 0; j < N; ++j) {
    if (j == i) continue;
    const float d = sqi + sq[j] - 2.0f * dot_rows(q, h + (size_t)j * s, D);
    // Candidates come in increasing index, so a tie never displaces an earlier one.
    if (d < bd[k - 1]) {
      int t = (int)k - 1;
      while (t > 0 && d < bd[t - 1]) {
        bd[t] = bd[t - 1];
        bi[t] = bi[t - 1];
        --t;
      }
      bd[t] = d;
      bi[t] = (int)j;
    }
  }
  for (uint t = 0; t < k; ++t) nbr[(size_t)i * k + t] = bi[t];
}

// The same neighbours as feature_knn, found without scanning every node.
// For any unit vector u, |a − b|² ≥ ((a − b)·u)², so with the nodes sorted
// by their projection p = h·u (host side, per frame, u the features' principal
// direction) a query walks outward from its own place in that order, nearer
// projection first, and stops once the projection gap alone exceeds its
// current k-th distance plus `margin`, a bound on the float rounding of the
// distance formula over every node (host: 1e-5 · (max |h|² + |h_i|²) terms). Ties are broken by lower index, as in feature_knn, so
// the result is the same set in the same order.
__kernel void feature_knn_pruned(const uint N, const uint D, const uint k, __global const float* h, const uint s,
                                 const uint off, __global const float* sq, __global const float* proj_sorted,
                                 __global const int* order, __global const int* rank, const float margin,
                                 __global int* nbr) {
  const uint i = get_global_id(0);
  if (i >= N) return;
  h += off;
  __global const float* q = h + (size_t)i * s;
  const float sqi = sq[i];
  const int pos = rank[i];
  const float pv = proj_sorted[pos];
  float bd[KNN_MAX_K];
  int bi[KNN_MAX_K];
  for (uint t = 0; t < k; ++t) {
    bd[t] = INFINITY;
    bi[t] = 0x7fffffff;
  }
  int lo = pos - 1, hi = pos + 1;
  while (lo >= 0 || hi < (int)N) {
    const float dl = lo >= 0 ? pv - proj_sorted[lo] : INFINITY;
    const float dh = hi < (int)N ? proj_sorted[hi] - pv : INFINITY;
    const float gap = fmin(dl, dh);
    const int at = dl <= dh ? lo-- : hi++;
    const uint j = (uint)order[at];
    if (gap * gap > bd[k - 1] + margin) {
      // Every node further out in this direction has a larger gap; the other
      // direction may still hold candidates.
      if (dl <= dh) lo = -1; else hi = (int)N;
      continue;
    }
    const float d = sqi + sq[j] - 2.0f * dot_rows(q, h + (size_t)j * s, D);
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
  for (uint t = 0; t < k; ++t) nbr[(size_t)i * k + t] = bi[t];
}

// Copies columns [off, off + D) of an N-row matrix with stride s into a
// compact N × D buffer (for the host's per-frame projection).
__kernel void copy_columns(const uint N, const uint D, __global const float* h, const uint s, const uint off,
                           __global float* out) {
  const uint id = get_global_id(0);
  if (id >= N * D) return;
  out[id] = h[(size_t)(id / D) * s + off + id % D];
}

// Coordinate-based upsampling with the load-time weights, then the first
// SIREN activation: pre[j, c] = sin(omega0 · Σ_q w[j, q] · r[idx[j, q], c])
// (r: N × H, the first reconstruction layer's affine map on the LR nodes).
__kernel void upsample_features(const uint M, const uint K, const uint H, __global const float* w,
                                __global const int* idx, __global const float* r, const float omega0,
                                __global float* pre) {
  const uint id = get_global_id(0);
  if (id >= M * H) return;
  const uint j = id / H, c = id % H;
  float s = 0.0f;
  for (uint q = 0; q < K; ++q) s += w[(size_t)j * K + q] * r[(size_t)idx[(size_t)j * K + q] * H + c];
  pre[id] = sin(omega0 * s);
}

// The embedded skip connection: out[j] += Σ_k w[j, k] · disp[nodes[j, k]]
// (the LR-embedded displacement of HR vertex j).
__kernel void add_embedded(const uint M, __global const int* nodes, __global const float* w,
                           __global const float* disp, __global float* out) {
  const uint id = get_global_id(0);
  if (id >= 3 * M) return;
  const uint j = id / 3, c = id % 3;
  float e = 0.0f;
  for (uint k = 0; k < 4; ++k) e += w[4 * j + k] * disp[3 * nodes[4 * j + k] + c];
  out[id] += e;
}
