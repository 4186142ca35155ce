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
// where its output is made so the next layer reads it once). Two kernels
// compute it: dense_simd for CPU devices and dense_tiled for GPUs (TILE ×
// TILE tiles staged in local memory, W out_dim × (K1 + K2) row-major).
#define ACTIVATE(v) (act == 1 ? ((v) < 0.0f ? slope * (v) : (v)) : act == 2 ? sin(omega0 * (v)) : (v))

// dense_simd: the CPU devices' dense layer. PoCL cannot vectorise a
// per-work-item dot product (a float reduction it may not reorder) nor, with
// a loop inside, across work-items (measured: a row-per-work-item kernel ran
// at ~7 GFLOP/s on 2 cores, scalar code); so the SIMD is
// explicit: one work-item computes DENSE_ROWS rows × 16 outputs as float16
// accumulators, each step one 16-wide weight load shared by all its rows.
// Wt is the weight transposed and zero-padded: K × P (P = out_dim rounded up
// to 16), bias padded to P; padded outputs are never written.
// The rows are unrolled by hand into named accumulators: PoCL neither
// unrolls the loop nor keeps a private array in registers.
#define DENSE_ROWS 8
#define ROWS8(X) X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7)

// sin for the SIREN activations of the CPU kernels. PoCL's sin is a
// full-range libm routine with branches (measured on ICT: two thirds of the
// upsampling stage and a third of the reconstruction). These arguments are
// modest, so: Cody-Waite reduction by π in three float parts with fma (x =
// kπ + r, |r| ≤ π/2; accurate while |k| < 2^20 or so), an odd degree-9
// polynomial in r fitted for this project (least squares, Lawson-reweighted
// towards minimax, coefficients rounded to float), and the sign of (−1)^k.
// Maximum error 1.3e-7 against double-precision sin for |x| ≤ 1e4 (PoCL's
// float sin: 7e-8); tested in RuntimeInference.FastSineMatchesSin.
float16 sin16(const float16 x) {
  const float16 k = rint(x * 0.318309886f);
  float16 r = fma(k, (float16)(-3.141592741e+00f), x);
  r = fma(k, (float16)(8.742277657e-08f), r);
  r = fma(k, (float16)(3.552713679e-15f), r);
  const float16 r2 = r * r;
  float16 p = fma(r2, (float16)(2.600053904e-06f), (float16)(-1.980661473e-04f));
  p = fma(p, r2, (float16)(8.333017118e-03f));
  p = fma(p, r2, (float16)(-1.666665673e-01f));
  p = fma(p * r2, r, r);
  return as_float16(as_int16(p) ^ (convert_int16(k) << 31));
}

// The check kernel behind that test: y = sin16(x), n a multiple of 16.
__kernel void sin16_values(__global const float* x, __global float* y) {
  const uint i = get_global_id(0) * 16;
  vstore16(sin16(vload16(0, x + i)), 0, y + i);
}

float16 activate16(const float16 v, const int act, const float omega0, const float slope) {
  if (act == 1) return select(v, slope * v, v < (float16)(0.0f));
  if (act == 2) return sin16(omega0 * v);
  return v;
}

void store16(const float16 v, __global float* y, const uint n) {
  if (n == 16) {
    vstore16(v, 0, y);
  } else {
    float t[16];
    vstore16(v, 0, t);
    for (uint c = 0; c < n; ++c) y[c] = t[c];
  }
}

// The body of both CPU dense kernels: 16 × halves outputs per work-item
// (halves is a literal at each call, so the unused half compiles away).
// dense_simd32 (halves = 2) is for layers whose padded width P is a
// multiple of 32: each step then has two weight loads and 8 broadcasts
// feeding 16 fmas instead of one load and 8 broadcasts feeding 8, so the
// loop is bound by the fmas rather than by the load ports, and 16
// independent accumulators cover the fma latency. Each output's sum is the
// same fma chain in the same order either way, so the results are
// bit-identical (tested).
inline void dense_simd_rows(const uint halves, const uint rows, const uint out_dim, const uint P, const uint K1,
                            const uint K2, __global const float* a1, const uint s1, const uint off1,
                            __global const float* a2, const uint s2, const uint off2, __global const float* Wt,
                            __global const float* bias, __global float* out, const uint out_stride,
                            const uint out_off, const int act, const float omega0, const float slope) {
  const uint width = 16 * halves, blocks = P / width, id = get_global_id(0);
  const uint row0 = (id / blocks) * DENSE_ROWS, o0 = (id % blocks) * width;
  if (row0 >= rows) return;
  const float16 b0 = vload16(0, bias + o0), b1 = halves == 2 ? vload16(0, bias + o0 + 16) : b0;
  // Rows past the end repeat the last one (read, never written).
#define DECLARE(q)                                   \
  const uint r##q = min(row0 + q, rows - 1);           \
  __global const float* x##q = a1 + off1 + (size_t)r##q * s1; \
  __global const float* z##q = a2 + off2 + (size_t)r##q * s2; \
  float16 acc##q = b0, bcc##q = b1;
  ROWS8(DECLARE)
#undef DECLARE
#define STEP_FROM(src, q)                      \
  {                                            \
    const float16 v = (float16)(src##q[k]);    \
    acc##q = fma(v, wk, acc##q);               \
    if (halves == 2) bcc##q = fma(v, vk, bcc##q); \
  }
#define STEP_X(q) STEP_FROM(x, q)
#define STEP_Z(q) STEP_FROM(z, q)
  __global const float* w = Wt + o0;
  for (uint k = 0; k < K1; ++k) {
    const float16 wk = vload16(0, w + (size_t)k * P), vk = halves == 2 ? vload16(0, w + (size_t)k * P + 16) : wk;
    ROWS8(STEP_X)
  }
  w += (size_t)K1 * P;
  for (uint k = 0; k < K2; ++k) {
    const float16 wk = vload16(0, w + (size_t)k * P), vk = halves == 2 ? vload16(0, w + (size_t)k * P + 16) : wk;
    ROWS8(STEP_Z)
  }
#undef STEP_Z
#undef STEP_X
#undef STEP_FROM
  out += out_off + o0;
  const uint n0 = min(16u, out_dim - o0), n1 = halves == 2 && out_dim > o0 + 16 ? min(16u, out_dim - o0 - 16) : 0u;
#define STORE(q)                                                                                     \
  if (row0 + q < rows) {                                                                             \
    store16(activate16(acc##q, act, omega0, slope), out + (size_t)(row0 + q) * out_stride, n0);      \
    if (n1 > 0) store16(activate16(bcc##q, act, omega0, slope), out + (size_t)(row0 + q) * out_stride + 16, n1); \
  }
  ROWS8(STORE)
#undef STORE
}

#define DENSE_SIMD_ARGS                                                                                         \
  const uint rows, const uint out_dim, const uint P, const uint K1, const uint K2, __global const float *a1,     \
      const uint s1, const uint off1, __global const float *a2, const uint s2, const uint off2,                 \
      __global const float *Wt, __global const float *bias, __global float *out, const uint out_stride,         \
      const uint out_off, const int act, const float omega0, const float slope
#define DENSE_SIMD_PASS rows, out_dim, P, K1, K2, a1, s1, off1, a2, s2, off2, Wt, bias, out, out_stride, out_off, act, omega0, slope
__kernel void dense_simd(DENSE_SIMD_ARGS) { dense_simd_rows(1, DENSE_SIMD_PASS); }
__kernel void dense_simd32(DENSE_SIMD_ARGS) { dense_simd_rows(2, DENSE_SIMD_PASS); }
#undef DENSE_SIMD_PASS
#undef DENSE_SIMD_ARGS

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
// edge_max and pool_columns for CPU devices, 16 channels per work-item (D
// a multiple of 16): the per-element versions loop over neighbours or rows,
// which PoCL leaves scalar. edge_max_simd does the same operations per lane
// (bit-identical); pool_columns_simd sums each column in row order.
__kernel void edge_max_simd(const uint N, const uint D, const uint k, __global const float* self,
                            __global const float* other, __global const int* nbr, const float slope,
                            __global float* y) {
  const uint blocks = D / 16, id = get_global_id(0);
  const uint i = id / blocks, c0 = (id % blocks) * 16;
  if (i >= N) return;
  const float16 s = vload16(0, self + (size_t)i * D + c0);
  float16 best = (float16)(-INFINITY);
  for (uint q = 0; q < k; ++q) {
    const float16 v = s + vload16(0, other + (size_t)nbr[(size_t)i * k + q] * D + c0);
    best = fmax(best, select(v, v * slope, v < (float16)(0.0f)));
  }
  vstore16(best, 0, y + (size_t)i * D + c0);
}

__kernel void pool_columns_simd(const uint N, const uint D, __global const float* y, __global float* pooled) {
  const uint c0 = get_global_id(0) * 16;
  if (c0 >= D) return;
  float16 m = (float16)(-INFINITY), s = (float16)(0.0f);
  for (uint i = 0; i < N; ++i) {
    const float16 v = vload16(0, y + (size_t)i * D + c0);
    m = fmax(m, v);
    s += v;
  }
  vstore16(m, 0, pooled + c0);
  vstore16(s / (float)N, 0, pooled + D + c0);
}

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

// a·b over D floats, accumulated in index order with fma: the order (and
// rounding) of feature_knn_simd's per-lane sums, so that every k-NN variant
// sees bit-identical distances and picks the same neighbours.
float dot_rows(__global const float* a, __global const float* b, const uint D) {
  float t = 0.0f;
  for (uint c = 0; c < D; ++c) t = fma(a[c], b[c], t);
  return t;
}

// A query's k best before any candidate: no node (KNN_NONE, above every
// index so that the ordered insertion's ties never prefer it) at +∞.
#define KNN_NONE 0x7fffffff
void knn_init(const uint k, float* bd, int* bi) {
  for (uint t = 0; t < k; ++t) {
    bd[t] = INFINITY;
    bi[t] = KNN_NONE;
  }
}

// Inserts candidate j at distance v into a query's k best (bd ascending,
// bi their indices) if it is strictly nearer than the k-th: with
// candidates offered in increasing index, ties keep the lower index.
void knn_insert(const float v, const int j, const uint k, float* bd, int* bi) {
  if (!(v < bd[k - 1])) return;
  int t = (int)k - 1;
  while (t > 0 && v < bd[t - 1]) {
    bd[t] = bd[t - 1];
    bi[t] = bi[t - 1];
    --t;
  }
  bd[t] = v;
  bi[t] = j;
}

// The same for candidates in any order: ordered by (distance, index).
bool knn_before(const float v, const int j, const float bv, const int bj) { return v < bv || (v == bv && j < bj); }
void knn_insert_ordered(const float v, const int j, const uint k, float* bd, int* bi) {
  if (!knn_before(v, j, bd[k - 1], bi[k - 1])) return;
  int t = (int)k - 1;
  while (t > 0 && knn_before(v, j, bd[t - 1], bi[t - 1])) {
    bd[t] = bd[t - 1];
    bi[t] = bi[t - 1];
    --t;
  }
  bd[t] = v;
  bi[t] = j;
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
  knn_init(k, bd, bi);
  for (uint j = 0; j < N; ++j) {
    if (j == i) continue;
    // Candidates come in increasing index, so a tie never displaces an earlier one.
    knn_insert(sqi + sq[j] - 2.0f * dot_rows(q, h + (size_t)j * s, D), (int)j, k, bd, bi);
  }
  for (uint t = 0; t < k; ++t) nbr[(size_t)i * k + t] = bi[t];
}

// Inserts 16 candidates (distances d, indices jb…jb + 15, in increasing
// index) into one query's sorted k best.
void knn_insert16(const float16 d, const uint jb, const uint k, float* bd, int* bi) {
  float t16[16];
  vstore16(d, 0, t16);
  for (uint l = 0; l < 16; ++l) knn_insert(t16[l], (int)(jb + l), k, bd, bi);
}

// The dot products of queries q0…q7 (named variables in the caller) with
// candidates j0…j0 + 31 of the transposed features hT (D × Np): a##n the
// lower 16 candidates, b##n the upper, accumulated in index order with fma.
// Named accumulators because PoCL keeps no private array in registers; two
// 16-wide candidate blocks per query so that each step's query value feeds
// two fmas (measured on ICT: 18.4 → 13.5 ms per frame against one block).
#define KNN_ZERO(n) float16 a##n = (float16)(0.0f), b##n = (float16)(0.0f);
#define KNN_STEP(n)                         \
  {                                         \
    const float16 v = (float16)(row[q##n]); \
    a##n = fma(v, ha, a##n);                \
    b##n = fma(v, hb, b##n);                \
  }
#define KNN_BLOCK_DOTS(hT, Np, D, j0)                                             \
  ROWS8(KNN_ZERO)                                                                 \
  for (uint c = 0; c < (D); ++c) {                                                \
    __global const float* row = (hT) + (size_t)c * (Np);                          \
    const float16 ha = vload16(0, row + (j0)), hb = vload16(0, row + (j0) + 16); \
    ROWS8(KNN_STEP)                                                               \
  }

// feature_knn with explicit SIMD for CPU devices: one work-item takes
// KNN_QUERIES queries and scans the candidates 32 at a time from the
// transposed features hT (D × Np, Np = N rounded up to 32, zero-padded;
// sq[N…Np) = +∞, so padding is never a candidate), so each step is two
// 16-wide loads shared by its queries. Same distance formula, same order and
// ties (candidates in increasing index, strict <).
#define KNN_QUERIES 8

// With `rows` (R node indices) it finds those nodes' neighbours only, the
// symmetric scan's fallback; without (NULL) every node's, R = N.
__kernel void feature_knn_simd(const uint N, const uint Np, const uint D, const uint k, __global const float* hT,
                               __global const float* sq, __global const int* rows, const uint R,
                               __global int* nbr) {
  const uint i0 = get_global_id(0) * KNN_QUERIES;
  if (i0 >= R) return;
  float bd[KNN_QUERIES][KNN_MAX_K];
  int bi[KNN_QUERIES][KNN_MAX_K];
  for (uint q = 0; q < KNN_QUERIES; ++q) knn_init(k, bd[q], bi[q]);
  // Per query: index, |h|² and the current k-th distance, as named scalars
  // (PoCL keeps no private array in registers).
#define QUERY(n)                                                        \
  const uint q##n = rows ? (uint)rows[min(i0 + n, R - 1)] : min(i0 + n, N - 1); \
  const float sqi##n = sq[q##n];                                        \
  float th##n = INFINITY;
  ROWS8(QUERY)
#undef QUERY
  const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  for (uint j0 = 0; j0 < Np; j0 += 32) {
    KNN_BLOCK_DOTS(hT, Np, D, j0)
    // Distances, and one test of all 256 against the queries' k-th
    // distances: after the first blocks nearly every block fails it, and the
    // per-query insertion (measured: half the k-NN time when it ran for
    // every query and block) is skipped.
    const float16 sqa = vload16(0, sq + j0), sqb = vload16(0, sq + j0 + 16);
#define DIST(n)                                                                         \
  const float16 da##n = sqi##n + sqa - 2.0f * a##n, db##n = sqi##n + sqb - 2.0f * b##n; \
  const int16 hit##n = (da##n < (float16)(th##n)) | (db##n < (float16)(th##n));
    ROWS8(DIST)
#undef DIST
    if (!any(hit0 | hit1 | hit2 | hit3 | hit4 | hit5 | hit6 | hit7)) continue;
    const int16 ja = (int)j0 + lane, jb = ja + 16;
    // The query itself is never its own neighbour.
#define INSERT(n)                                                                  \
  if (any(hit##n)) {                                                               \
    knn_insert16(select(da##n, (float16)(INFINITY), ja == (int)q##n), j0, k, bd[n], bi[n]); \
    knn_insert16(select(db##n, (float16)(INFINITY), jb == (int)q##n), j0 + 16, k, bd[n], bi[n]); \
    th##n = bd[n][k - 1];                                                          \
  }
    ROWS8(INSERT)
#undef INSERT
  }
  for (uint q = 0; q < KNN_QUERIES && i0 + q < R; ++q) {
    const size_t i = rows ? (size_t)rows[i0 + q] : i0 + q;
    for (uint t = 0; t < k; ++t) nbr[i * k + t] = bi[q][t];
  }
}

// ---- Symmetric k-NN (CPU devices) ----
// The distance formula is symmetric bit for bit (fma(a, b, t) = fma(b, a, t),
// sq_i + sq_j = sq_j + sq_i), so each pair is computed once: the work-item
// for queries i0…i0+7 scans only the 32-candidate blocks from its own one
// on and records a pair for its query (row side) and, off its own block,
// for the candidate (column side). Recording needs a bound on each row's
// k-th distance before the scan: tau_i, the k-th distance to known distinct
// other nodes (see knn_bounds), plus a margin for rounding. Every pair closer than tau_i is
// appended to row i's list (atomically: two work-items may append to one
// row); knn_select then sorts each list. A list that overflowed or came up
// short (impossible unless rounding beat the margin) is redone by a full
// scan, so the neighbours are exactly feature_knn's in every case.
#ifndef KNN_LIST  // the host sets it (ClInferenceOptions::knn_list)
#define KNN_LIST 64
#endif

// tau[i] for i < N (tau has Np entries; the padding's −∞ is set at load):
// the k-th smallest distance from i to its known neighbours and their known
// neighbours (distinct nodes; the second ring keeps the bound tight when the
// features move between frames), plus a margin for the formula's rounding
// (|sq_i| + |sq_j| in size). h is row-major (row stride s, first column
// off), so each distance reads contiguous rows.
__kernel void knn_bounds(const uint N, const uint D, const uint k, __global const float* h, const uint s,
                         const uint off, __global const float* sq, __global const int* known, __global float* tau) {
  const uint i = get_global_id(0);
  if (i >= N) return;
  h += off;
  __global const float* hi = h + (size_t)i * s;
  float bd[KNN_MAX_K];
  int bi[KNN_MAX_K];
  knn_init(k, bd, bi);
  float sqmax = 0.0f;
  for (uint a = 0; a <= k; ++a) {
    // a = 0: i's own known neighbours; a > 0: those of its (a−1)-th one.
    const int via = a == 0 ? (int)i : known[(size_t)i * k + a - 1];
    if (via < 0 || via >= (int)N) continue;
    for (uint b = 0; b < k; ++b) {
      const int j = known[(size_t)via * k + b];
      if (j < 0 || j >= (int)N || j == (int)i) continue;
      // 16 at a time (a bound need not match the scans' rounding: the margin covers it).
      __global const float* hj = h + (size_t)j * s;
      float16 acc = (float16)(0.0f);
      uint c = 0;
      for (; c + 16 <= D; c += 16) acc = fma(vload16(0, hi + c), vload16(0, hj + c), acc);
      const float8 a8 = acc.lo + acc.hi;
      const float4 a4 = a8.lo + a8.hi;
      float dot = (a4.x + a4.y) + (a4.z + a4.w);
      for (; c < D; ++c) dot = fma(hi[c], hj[c], dot);
      const float v = sq[i] + sq[j] - 2.0f * dot;
      if (!(v < bd[k - 1])) continue;
      // A node reached twice has the same distance: keep it once.
      bool fresh = true;
      for (uint t = 0; t < k; ++t) fresh = fresh && bi[t] != j;
      if (!fresh) continue;
      sqmax = fmax(sqmax, sq[j]);
      knn_insert(v, j, k, bd, bi);
    }
  }
  // Fewer than k distinct nodes known: no bound (every candidate is
  // recorded, and the lists overflow to a full scan).
  tau[i] = bi[k - 1] == KNN_NONE ? INFINITY : bd[k - 1] + 1e-5f * (sq[i] + sqmax);
}

void knn_append(__global volatile int* count, __global float* list_d, __global int* list_j, const uint row,
                const float d, const int j) {
  const int slot = atomic_inc(count + row);
  if (slot < KNN_LIST) {
    list_d[(size_t)row * KNN_LIST + slot] = d;
    list_j[(size_t)row * KNN_LIST + slot] = j;
  }
}

// Appends the lanes of one 16-candidate block (indices jb…) that beat the bound.
void knn_append_rows(const float16 d, const float th, const uint jb, const uint self, const uint row,
                     __global volatile int* count, __global float* list_d, __global int* list_j) {
  float t16[16];
  vstore16(d, 0, t16);
  for (uint l = 0; l < 16; ++l)
    if (t16[l] < th && jb + l != self) knn_append(count, list_d, list_j, row, t16[l], (int)(jb + l));
}

void knn_append_columns(const float16 d, __global const float* tau, const uint jb, const uint q,
                        __global volatile int* count, __global float* list_d, __global int* list_j) {
  float t16[16];
  vstore16(d, 0, t16);
  for (uint l = 0; l < 16; ++l)
    if (t16[l] < tau[jb + l]) knn_append(count, list_d, list_j, jb + l, t16[l], (int)q);
}

__kernel void feature_knn_symmetric(const uint N, const uint Np, const uint D, __global const float* hT,
                                    __global const float* sq, __global const float* tau,
                                    __global volatile int* count, __global float* list_d, __global int* list_j) {
  const uint i0 = get_global_id(0) * KNN_QUERIES;
  if (i0 >= N) return;
  // Queries past N repeat the last node with no bound, so they record nothing.
#define QUERY(n)                                      \
  const uint q##n = min(i0 + n, N - 1);               \
  const bool real##n = i0 + n < N;                    \
  const float sqi##n = sq[q##n];                      \
  const float th##n = real##n ? tau[q##n] : -INFINITY;
  ROWS8(QUERY)
#undef QUERY
  const uint own = i0 / 32 * 32;
  for (uint j0 = own; j0 < Np; j0 += 32) {
    KNN_BLOCK_DOTS(hT, Np, D, j0)
    const float16 sqa = vload16(0, sq + j0), sqb = vload16(0, sq + j0 + 16);
    // Off the own block the candidates' bounds apply too (column side);
    // in it every pair is some query's row side already.
    const bool off = j0 != own;
    const float16 ta = off ? vload16(0, tau + j0) : (float16)(-INFINITY);
    const float16 tb = off ? vload16(0, tau + j0 + 16) : (float16)(-INFINITY);
#define DIST(n)                                                                                \
  const float16 da##n = sqi##n + sqa - 2.0f * a##n, db##n = sqi##n + sqb - 2.0f * b##n;        \
  const int16 rowhit##n = (da##n < (float16)(th##n)) | (db##n < (float16)(th##n));             \
  const int16 colhit##n = real##n ? (da##n < ta) | (db##n < tb) : (int16)(0);
    ROWS8(DIST)
#undef DIST
    if (!any(rowhit0 | rowhit1 | rowhit2 | rowhit3 | rowhit4 | rowhit5 | rowhit6 | rowhit7 | colhit0 | colhit1 |
             colhit2 | colhit3 | colhit4 | colhit5 | colhit6 | colhit7))
      continue;
#define RECORD(n)                                                                  \
  if (any(rowhit##n)) {                                                            \
    knn_append_rows(da##n, th##n, j0, q##n, q##n, count, list_d, list_j);          \
    knn_append_rows(db##n, th##n, j0 + 16, q##n, q##n, count, list_d, list_j);     \
  }                                                                                \
  if (any(colhit##n)) {                                                            \
    knn_append_columns(da##n, tau, j0, q##n, count, list_d, list_j);               \
    knn_append_columns(db##n, tau, j0 + 16, q##n, count, list_d, list_j);          \
  }
    ROWS8(RECORD)
#undef RECORD
  }
}

// Each row's k nearest from its list, ordered by (distance, index) as the
// full scan orders them. Rows whose list overflowed (or came up short) are
// appended to `redo` (count in redo_count[0]) for feature_knn_simd's full
// scan. Resets the list counts for the next frame; the result is the next
// frame's known neighbours.
__kernel void knn_select(const uint N, const uint k, __global int* count, __global const float* list_d,
                         __global const int* list_j, __global int* nbr, __global volatile int* redo_count,
                         __global int* redo) {
  const uint i = get_global_id(0);
  if (i >= N) return;
  const int n = count[i];
  count[i] = 0;
  if (n < (int)k || n > KNN_LIST) {
    redo[atomic_inc(redo_count)] = (int)i;
    return;
  }
  float bd[KNN_MAX_K];
  int bi[KNN_MAX_K];
  knn_init(k, bd, bi);
  for (int e = 0; e < n; ++e) {
    knn_insert_ordered(list_d[(size_t)i * KNN_LIST + e], list_j[(size_t)i * KNN_LIST + e], k, bd, bi);
  }
  for (uint t = 0; t < k; ++t) nbr[(size_t)i * k + t] = bi[t];
}

// hT[c, i] = h[i, off + c] for i < N, 0 for N ≤ i < Np (for the k-NN
// scans), 16 rows per work-item: 16 strided loads, one vector store; work-item
// g takes column g mod D and rows 16 (g / D) on.
__kernel void transpose_columns16(const uint N, const uint Np, const uint D, __global const float* h, const uint s,
                                  const uint off, __global float* hT) {
  const uint id = get_global_id(0), blocks = Np / 16;
  if (id >= blocks * D) return;
  // Consecutive work-items take consecutive columns of the same 16 rows,
  // which then stay in L1.
  const uint c = id % D, i0 = 16 * (id / D);
  float v[16];
  for (uint l = 0; l < 16; ++l) v[l] = i0 + l < N ? h[(size_t)(i0 + l) * s + off + c] : 0.0f;
  vstore16(vload16(0, v), 0, hT + (size_t)c * Np + i0);
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
  knn_init(k, bd, bi);
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
    knn_insert_ordered(sqi + sq[j] - 2.0f * dot_rows(q, h + (size_t)j * s, D), (int)j, k, bd, bi);
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

// upsample_features for CPU devices: one work-item per HR vertex and 16
// columns (r and pre with row stride P, a multiple of 16).
__kernel void upsample_features_simd(const uint M, const uint K, const uint P, __global const float* w,
                                     __global const int* idx, __global const float* r, const float omega0,
                                     __global float* pre) {
  const uint blocks = P / 16, id = get_global_id(0);
  const uint j = id / blocks, c0 = (id % blocks) * 16;
  if (j >= M) return;
  float16 s = (float16)(0.0f);
  for (uint q = 0; q < K; ++q) s = fma((float16)(w[(size_t)j * K + q]), vload16(0, r + (size_t)idx[(size_t)j * K + q] * P + c0), s);
  vstore16(sin16(omega0 * s), 0, pre + (size_t)j * P + c0);
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
