#include "solvers/linalg/supernodal_solve.h"

#include <cblas.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>

#include "intrinsic/core/errors.h"
#include "solvers/linalg/flush_denormals.h"
#include "solvers/linalg/huge_pages.h"
#include "solvers/linalg/lanes.h"
#include "solvers/linalg/parallel.h"

namespace ifem::solvers {

namespace {

using Int64 = std::int64_t;
using lanes::Lanes;
using lanes::load;
using lanes::store;

// A subtree of the elimination tree: supernodes [first, last] (last is its root), whose columns
// end before col_end; rows at or past col_end are its ancestors' (the serial top).
struct Subtree {
  int first = 0, last = 0, col_end = 0;
};

// One supernode's dense block: nsrow × nscol column-major values L, row indices R, first column k1.
template <class Real>
struct Block {
  const Real* L;
  const int* R;
  int nscol, nsrow, k1;
};

// Where a forward pass inside a subtree sends the updates of its ancestors' rows: a bin's own
// accumulator (compact top numbering), so that two bins never write the same row.
struct TopAccumulator {
  double* acc = nullptr;
  const int* top_index = nullptr;
  int col_end = 0;
};

// A supernode's block as double: the factor's own values, or the float values converted into
// `scratch` (nsrow × nscol, column-major) so that the dense kernels below run in double.
template <class Real>
const double* block_values(const Block<Real>& b, double* scratch) {
  if constexpr (std::is_same_v<Real, double>) {
    (void)scratch;
    return b.L;
  } else {
    const Int64 size = Int64(b.nsrow) * b.nscol;
    for (Int64 i = 0; i < size; ++i) scratch[i] = double(b.L[i]);
    return scratch;
  }
}

// Supernodes up to this many columns solve a single right-hand side with the loops below, one
// pass over each column, rather than BLAS dtrsv + dgemv: OpenBLAS's dtrsv takes a lock-guarded
// buffer on every call, and on the mean supernode (7.7 columns × 28 rows) the calls cost more
// than the arithmetic (one 1M-face query: 0.185 s with BLAS, docs/decisions.md). The loops read a
// float factor directly, converting each entry as it is used. Several right-hand sides on such
// supernodes, and on AVX-512 hosts on every supernode, go through the chunk kernels further down
// (forward_small, backward_small; block_kernel_limit()).
constexpr int kSmallSupernode = 64;

// Σ a[i]·b[i] over n entries, in four independent sums (a fixed order: the same bits on every
// thread count).
template <class Real>
double dot(const Real* a, const double* b, int n) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    s0 += double(a[i]) * b[i];
    s1 += double(a[i + 1]) * b[i + 1];
    s2 += double(a[i + 2]) * b[i + 2];
    s3 += double(a[i + 3]) * b[i + 3];
  }
  for (; i < n; ++i) s0 += double(a[i]) * b[i];
  return (s0 + s1) + (s2 + s3);
}

// Forward substitution of a small supernode for one right-hand side: y ← L11⁻¹ y in place and
// T ← L21 y (m entries), one column at a time.
template <class Real>
void forward_one(const Block<Real>& b, double* y, double* T) {
  const int nscol = b.nscol, m = b.nsrow - b.nscol;
  std::fill(T, T + m, 0.0);
  for (int j = 0; j < nscol; ++j) {
    const Real* col = b.L + Int64(j) * b.nsrow;
    const double yj = y[j] / double(col[j]);
    y[j] = yj;
    for (int i = j + 1; i < nscol; ++i) y[i] -= double(col[i]) * yj;
    const Real* below = col + nscol;
    for (int i = 0; i < m; ++i) T[i] += double(below[i]) * yj;
  }
}

// Backward substitution of a small supernode for one right-hand side: y ← L11⁻ᵀ (y − L21ᵀ g),
// where Z holds [y; g] (nsrow entries: the supernode's rows, g gathered from the final rows below)
// so that each column is one dot product.
template <class Real>
void backward_one(const Block<Real>& b, double* y, double* Z) {
  const int nscol = b.nscol, nsrow = b.nsrow;
  std::copy(y, y + nscol, Z);
  for (int j = nscol - 1; j >= 0; --j) {
    const Real* col = b.L + Int64(j) * nsrow;
    Z[j] = (Z[j] - dot(col + j + 1, Z + j + 1, nsrow - j - 1)) / double(col[j]);
  }
  std::copy(Z, Z + nscol, y);
}

// The kernels of a supernode for k > 1 right-hand sides (up to 64 columns; every supernode on
// AVX-512 hosts, block_kernel_limit()), on W (n × k, row-major: row i is the contiguous W + i·k),
// in chunks of C columns held in registers. A solve of 32 sources at
// 1M faces spent 22 GFlop/s in OpenBLAS's dgemm/dtrsm on the mean supernode (7.7 columns × 28
// rows), which pack both operands per call; these loops run over L11 and L21 once per chunk
// (the block stays in L1) and fuse the update with the scatter (forward) and the gather with
// the update (backward). Each is compiled for AVX-512, AVX2 + FMA and the baseline ISA and picked
// at load time (target_clones); the order of every sum is fixed, so the bits do not depend on
// the thread count.
// A small supernode's dense block as the chunk kernels read it (double values).
struct DenseBlock {
  const double* L;   // nsrow × nscol, column-major, leading dimension ld
  const int* below;  // the m = ld − nscol rows under the diagonal block
  int ld, nscol, k1;
};

// The kernels work on NV chunks of C columns side by side (C = 8, 4, 2, 1 lanes per vector; NV
// = 1, or 2 and 4 for C = 8 on AVX-512 hosts: a row's 16 or 32 columns at once). Per lane the
// operations and their order do not depend on C or NV, so a column gets the same bits in any of
// them (test SupernodalSolve.ColumnBitsDoNotDependOnTheKernel). With NV > 1 the chunks'
// independent chains overlap (the triangular solves are latency chains through memory) and each
// gathered or scattered row is read whole at once rather than one 64-byte line per chunk pass:
// a 1M-face block of 32 sources 0.376 → 0.333 s (BENCHMARKS.md, "Blocks of sources, session
// 13"). They hold 4·NV + NV vectors: NV > 1 only where AVX-512's 32 registers do
// (wide_kernels()).

// Column j of L11 on the chunks' columns: y_j ← y_j / L_jj into y (NV vectors, also stored), then
// y_i −= L_ij y_j for the rows j < i < i_end.
template <int C, int NV>
[[gnu::always_inline]] inline void lower_solve_column(const DenseBlock& b, double* Y, int k, int j,
                                                      int i_end, typename Lanes<C>::V* y) {
  const double* col = b.L + Int64(j) * b.ld;
  double* yj = Y + Int64(j) * k;
  const double inv = 1.0 / col[j];
#pragma GCC unroll 4
  for (int v = 0; v < NV; ++v) {
    y[v] = load<C>(yj + C * v) * inv;
    store<C>(yj + C * v, y[v]);
  }
  for (int i = j + 1; i < i_end; ++i) {
    double* yi = Y + Int64(i) * k;
    const double l = col[i];
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) store<C>(yi + C * v, load<C>(yi + C * v) - l * y[v]);
  }
}

// L11 Y = B for the chunks' columns of the supernode's rows, j ascending (per lane the order of
// the updates of each row is fixed). Four columns of L11 at a time: their 4 × 4 diagonal block
// column by column, then each row under it loaded and stored once for the four updates (one at a
// time, a row was loaded and stored per column: a 1M-face block of 32 sources 0.375 -> 0.354 s
// and 0.370 -> 0.346 s, igea 0.101 -> 0.099 s, medians, in turns in one process); the same
// operations in the same order per lane.
template <int C, int NV>
[[gnu::always_inline]] inline void lower_solve_chunks(const DenseBlock& b, double* Y, int k) {
  using V = typename Lanes<C>::V;
  int j0 = 0;
  for (; j0 + 4 <= b.nscol; j0 += 4) {
    V y[4][NV];
#pragma GCC unroll 4
    for (int q = 0; q < 4; ++q) lower_solve_column<C, NV>(b, Y, k, j0 + q, j0 + 4, y[q]);
    const double* l0 = b.L + Int64(j0) * b.ld;
    const double* l1 = l0 + b.ld;
    const double* l2 = l1 + b.ld;
    const double* l3 = l2 + b.ld;
    for (int i = j0 + 4; i < b.nscol; ++i) {
      double* yi = Y + Int64(i) * k;
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) {
        V a = load<C>(yi + C * v);
        a -= l0[i] * y[0][v];
        a -= l1[i] * y[1][v];
        a -= l2[i] * y[2][v];
        a -= l3[i] * y[3][v];
        store<C>(yi + C * v, a);
      }
    }
  }
  for (int j = j0; j < b.nscol; ++j) {
    V y[NV];
    lower_solve_column<C, NV>(b, Y, k, j, b.nscol, y);
  }
}

// The rows a backward sum reads: rows of Y in order (L11), or rows of W gathered through the
// supernode's row list (L21), from column c0.
struct OwnRows {
  const double* Y;
  int k;
  [[gnu::always_inline]] const double* operator()(int i) const { return Y + Int64(i) * k; }
};
struct GatheredRows {
  const double* W;
  const int* below;
  int k, c0;
  [[gnu::always_inline]] const double* operator()(int r) const {
    return W + Int64(below[r]) * k + c0;
  }
};

// a[q] = Σ_r l[q][r] · row(r) over r in [r0, r1), for Q columns of L at once: each row loaded
// once for the Q columns, Q streams down the columns of L; each sum in the order of r, whatever
// Q (so a column's bits do not depend on how the columns are grouped).
template <int C, int NV, int Q, class Rows>
[[gnu::always_inline]] inline void column_sums(const double* const (&l)[Q], int r0, int r1,
                                               Rows row, typename Lanes<C>::V (&a)[Q][NV]) {
  using V = typename Lanes<C>::V;
  for (int r = r0; r < r1; ++r) {
    const double* w = row(r);
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) {
      const V x = load<C>(w + C * v);
#pragma GCC unroll 4
      for (int q = 0; q < Q; ++q) a[q][v] += l[q][r] * x;
    }
  }
}

// Columns [j0, j0 + Q) of lower_transpose_solve_chunks(): their sums over the rows of L11 below
// them first (each row of Y loaded once for the Q columns, Q streams down the columns of L11),
// then their Q × Q diagonal block from its last column.
template <int C, int NV, int Q>
[[gnu::always_inline]] inline void transpose_solve_columns(const DenseBlock& b, double* Y, int k,
                                                           int j0) {
  using V = typename Lanes<C>::V;
  const double* l[Q];
#pragma GCC unroll 4
  for (int q = 0; q < Q; ++q) l[q] = b.L + Int64(j0 + q) * b.ld;
  V a[Q][NV] = {};
  column_sums<C, NV, Q>(l, j0 + Q, b.nscol, OwnRows{Y, k}, a);
#pragma GCC unroll 4
  for (int q = Q - 1; q >= 0; --q) {
    double* yj = Y + Int64(j0 + q) * k;
    V acc[NV];
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) acc[v] = load<C>(yj + C * v) - a[q][v];
    for (int i = j0 + q + 1; i < j0 + Q; ++i) {
      const double* yi = Y + Int64(i) * k;
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) acc[v] -= l[q][i] * load<C>(yi + C * v);
    }
    const double inv = 1.0 / l[q][j0 + q];
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) store<C>(yj + C * v, acc[v] * inv);
  }
}

// L11ᵀ X = B for the chunks' columns, four columns of L11 at a time from the last (the first
// nscol mod 4 together last). One column at a time, each row of Y was loaded once per column
// for a single FMA: a 1M-face block of 32 sources, heat solve 66 -> 63 ms and Poisson solve
// 105 -> 100 ms (medians, in turns in one process; docs/decisions.md, "Blocks of sources,
// session 14").
template <int C, int NV>
[[gnu::always_inline]] inline void lower_transpose_solve_chunks(const DenseBlock& b, double* Y,
                                                                int k) {
  int j1 = b.nscol;
  for (; j1 >= 4; j1 -= 4) transpose_solve_columns<C, NV, 4>(b, Y, k, j1 - 4);
  switch (j1) {
    case 3:
      transpose_solve_columns<C, NV, 3>(b, Y, k, 0);
      break;
    case 2:
      transpose_solve_columns<C, NV, 2>(b, Y, k, 0);
      break;
    case 1:
      transpose_solve_columns<C, NV, 1>(b, Y, k, 0);
      break;
    default:
      break;
  }
}

// The row of W (or of the bin's top accumulator) that an update of factor row i goes to.
inline double* update_row(const TopAccumulator& top, double* W, int i, int k) {
  return top.acc && i >= top.col_end ? top.acc + Int64(top.top_index[i]) * k : W + Int64(i) * k;
}

// Forward pass of one supernode on the chunks from column c0 (Y: its rows there): solve with
// L11, then W[below[r]] −= L21[r, :] Y, four rows of L21 at a time.
template <int C, int NV>
[[gnu::always_inline]] inline void forward_chunks(const DenseBlock& b, double* W, int k, int c0,
                                                  const TopAccumulator& top) {
  using V = typename Lanes<C>::V;
  double* Y = W + Int64(b.k1) * k + c0;
  lower_solve_chunks<C, NV>(b, Y, k);
  const int m = b.ld - b.nscol;
  const double* L21 = b.L + b.nscol;
  int r = 0;
  for (; r + 4 <= m; r += 4) {
    V a[4][NV] = {};
    for (int j = 0; j < b.nscol; ++j) {
      const double* l = L21 + Int64(j) * b.ld + r;
      const double* yj = Y + Int64(j) * k;
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) {
        const V y = load<C>(yj + C * v);
        a[0][v] += l[0] * y;
        a[1][v] += l[1] * y;
        a[2][v] += l[2] * y;
        a[3][v] += l[3] * y;
      }
    }
#pragma GCC unroll 4
    for (int q = 0; q < 4; ++q) {
      double* dst = update_row(top, W, b.below[r + q], k) + c0;
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) store<C>(dst + C * v, load<C>(dst + C * v) - a[q][v]);
    }
  }
  for (; r < m; ++r) {
    V acc[NV] = {};
    for (int j = 0; j < b.nscol; ++j) {
      const double l = L21[Int64(j) * b.ld + r];
      const double* yj = Y + Int64(j) * k;
#pragma GCC unroll 4
      for (int v = 0; v < NV; ++v) acc[v] += l * load<C>(yj + C * v);
    }
    double* dst = update_row(top, W, b.below[r], k) + c0;
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) store<C>(dst + C * v, load<C>(dst + C * v) - acc[v]);
  }
}

// Y_j −= Σ_r L21[r, j] W[below[r]] for the Q columns [j, j + Q) of the supernode at once (one
// pass over the rows below; each column's sum in the order of r, whatever Q).
template <int C, int NV, int Q>
[[gnu::always_inline]] inline void backward_columns(const DenseBlock& b, const double* W, int k,
                                                    int c0, double* Y, int j) {
  using V = typename Lanes<C>::V;
  const double* l[Q];
#pragma GCC unroll 4
  for (int q = 0; q < Q; ++q) l[q] = b.L + b.nscol + Int64(j + q) * b.ld;
  V a[Q][NV] = {};
  column_sums<C, NV, Q>(l, 0, b.ld - b.nscol, GatheredRows{W, b.below, k, c0}, a);
#pragma GCC unroll 4
  for (int q = 0; q < Q; ++q) {
    double* yj = Y + Int64(j + q) * k;
#pragma GCC unroll 4
    for (int v = 0; v < NV; ++v) store<C>(yj + C * v, load<C>(yj + C * v) - a[q][v]);
  }
}

// Backward pass of one supernode on the chunks from column c0: Y_j −= Σ_r L21[r, j] W[below[r]]
// (the rows below are final), four columns of L21 at a time (the last nscol mod 4 together), then
// solve with L11ᵀ.
template <int C, int NV>
[[gnu::always_inline]] inline void backward_chunks(const DenseBlock& b, double* W, int k, int c0) {
  double* Y = W + Int64(b.k1) * k + c0;
  int j = 0;
  for (; j + 4 <= b.nscol; j += 4) backward_columns<C, NV, 4>(b, W, k, c0, Y, j);
  switch (b.nscol - j) {  // the last nscol mod 4 columns in one pass over the rows below
    case 3:
      backward_columns<C, NV, 3>(b, W, k, c0, Y, j);
      break;
    case 2:
      backward_columns<C, NV, 2>(b, W, k, c0, Y, j);
      break;
    case 1:
      backward_columns<C, NV, 1>(b, W, k, c0, Y, j);
      break;
    default:
      break;
  }
  lower_transpose_solve_chunks<C, NV>(b, Y, k);
}

// Whether the kernels take 16 or 32 columns at once (NV = 2, 4 chunks of 8): they hold 4·NV + NV
// vectors of 8 doubles, which AVX-512's 32 registers do; with AVX2's 16 (two per vector) they
// would spill. Also where the clones are off (sanitizer builds): there the same source runs on
// baseline vectors, slower but correct, so that the sanitizers see the paths AVX-512 hosts run.
bool wide_kernels() { return lanes::host_has_avx512(); }

// The widest supernode (columns) that several right-hand sides solve through our loops rather
// than BLAS dtrsm + dgemm: every one where wide_kernels(). OpenBLAS packs both operands
// on every call, and a supernode's block is used for only the k columns of one pass: igea, a
// block of 32 sources spent 20 % of its samples in dgemm and its packing routines; with every
// supernode in our loops, in one process taking turns, 1M faces 0.337 -> 0.299 s (median of 9)
// and 0.344 -> 0.324 (11), 100k 0.0287 -> 0.0270 s, igea 0.0856 -> 0.0819 s, rocketship
// 0.0090 -> 0.0089 s. Elsewhere (no AVX-512) up to kSmallSupernode, as before.
int block_kernel_limit() {
  static const int limit = wide_kernels() ? std::numeric_limits<int>::max() : kSmallSupernode;
  return limit;
}

// A range [begin, end) of the k columns (a forward pass may skip columns that are zero in a
// supernode's rows and below: point sources outside its subtree).
struct Columns {
  int begin = 0, end = 0;
};

// A rank-one term subtracted from the right-hand sides, W − rows·sumsᵀ (rows: n values in the
// factor's order, sums: k), row by row as the forward pass reaches each (no sweep of its own).
struct RankOne {
  const double* rows = nullptr;
  const double* sums = nullptr;
};

// The chunk kernels over columns [c.begin, c.end) of the k: on AVX-512 hosts 32 and then 16 at
// once, then chunks of 8, then 4, 2 and 1 for the rest.
IFEM_HOST_CLONES void forward_small(const DenseBlock& b, double* W, int k,
                                    const TopAccumulator& top, Columns c) {
  int c0 = c.begin;
  if (wide_kernels()) {
    for (; c0 + 32 <= c.end; c0 += 32) forward_chunks<8, 4>(b, W, k, c0, top);
    if (c0 + 16 <= c.end) forward_chunks<8, 2>(b, W, k, c0, top), c0 += 16;
  }
  for (; c0 + 8 <= c.end; c0 += 8) forward_chunks<8, 1>(b, W, k, c0, top);
  if (c0 + 4 <= c.end) forward_chunks<4, 1>(b, W, k, c0, top), c0 += 4;
  if (c0 + 2 <= c.end) forward_chunks<2, 1>(b, W, k, c0, top), c0 += 2;
  if (c0 < c.end) forward_chunks<1, 1>(b, W, k, c0, top);
}

IFEM_HOST_CLONES void backward_small(const DenseBlock& b, double* W, int k, Columns c) {
  int c0 = c.begin;
  if (wide_kernels()) {
    for (; c0 + 32 <= c.end; c0 += 32) backward_chunks<8, 4>(b, W, k, c0);
    if (c0 + 16 <= c.end) backward_chunks<8, 2>(b, W, k, c0), c0 += 16;
  }
  for (; c0 + 8 <= c.end; c0 += 8) backward_chunks<8, 1>(b, W, k, c0);
  if (c0 + 4 <= c.end) backward_chunks<4, 1>(b, W, k, c0), c0 += 4;
  if (c0 + 2 <= c.end) backward_chunks<2, 1>(b, W, k, c0), c0 += 2;
  if (c0 < c.end) backward_chunks<1, 1>(b, W, k, c0);
}

// Forward substitution of one supernode on W (n × k, row-major), as CHOLMOD's own supernodal
// solve does: solve with the diagonal block, then subtract the off-diagonal block's product from
// the rows below (T: scratch, m × k; S: scratch for a converted float block). Small supernodes go
// through the loops above (one right-hand side), supernodes up to block_kernel_limit() through
// the chunk kernels (several), larger ones through BLAS; several right-hand sides on columns c
// only (the others stay as they are).
template <class Real>
void forward_block(const Block<Real>& b, double* W, int k, double* T, double* S,
                   const TopAccumulator& top, Columns c, const RankOne& shift = {}) {
  const int m = b.nsrow - b.nscol, ld = b.nsrow, kc = c.end - c.begin;
  double* Y = W + Int64(b.k1) * k + c.begin;
  if (shift.rows) {
    for (int i = 0; i < b.nscol; ++i) {
      const double r = shift.rows[b.k1 + i];
      double* y = Y + Int64(i) * k;
      for (int j = 0; j < kc; ++j) y[j] -= r * shift.sums[c.begin + j];
    }
  }
  const bool small = k == 1 && b.nscol <= kSmallSupernode;
  const double* L = small ? nullptr : block_values(b, S);
  if (small) {
    forward_one(b, Y, T);
  } else if (k == 1) {
    cblas_dtrsv(CblasColMajor, CblasLower, CblasNoTrans, CblasNonUnit, b.nscol, L, ld, Y, 1);
    if (m == 0) return;
    cblas_dgemv(CblasColMajor, CblasNoTrans, m, b.nscol, 1.0, L + b.nscol, ld, Y, 1, 0.0, T, 1);
  } else if (b.nscol <= block_kernel_limit()) {
    forward_small(DenseBlock{L, b.R + b.nscol, ld, b.nscol, b.k1}, W, k, top, c);
    return;
  } else {
    // Y is Yᵀ column-major (kc × nscol, leading dimension k): L11 Y = B ⇔ Yᵀ L11ᵀ = Bᵀ;
    // Tᵀ = Yᵀ L21ᵀ (kc × m)
    cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, kc, b.nscol, 1.0,
                L, ld, Y, k);
    if (m == 0) return;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, kc, m, b.nscol, 1.0, Y, k, L + b.nscol, ld,
                0.0, T, kc);
  }
  const int* rows = b.R + b.nscol;
  for (int r = 0; r < m; ++r) {
    double* dst = update_row(top, W, rows[r], k) + c.begin;
    const double* tr = T + Int64(r) * kc;
    for (int j = 0; j < kc; ++j) dst[j] -= tr[j];
  }
}

// Backward substitution of one supernode: subtract the off-diagonal block's transpose times the
// (final) rows below, gathered into G (m × kc), then solve with the diagonal block's transpose;
// several right-hand sides on columns c only (kc of them).
template <class Real>
void backward_block(const Block<Real>& b, double* W, int k, double* G, double* S, Columns c) {
  const int m = b.nsrow - b.nscol, ld = b.nsrow, kc = c.end - c.begin;
  double* Y = W + Int64(b.k1) * k + c.begin;
  if (k == 1 && b.nscol <= kSmallSupernode) {
    const int* rows = b.R + b.nscol;
    for (int r = 0; r < m; ++r) G[b.nscol + r] = W[rows[r]];
    backward_one(b, Y, G);
    return;
  }
  const double* L = block_values(b, S);
  if (k > 1 && b.nscol <= block_kernel_limit()) {
    backward_small(DenseBlock{L, b.R + b.nscol, ld, b.nscol, b.k1}, W, k, c);
    return;
  }
  if (m > 0) {
    const int* rows = b.R + b.nscol;
    for (int r = 0; r < m; ++r) {
      const double* src = W + Int64(rows[r]) * k + c.begin;
      std::copy(src, src + kc, G + Int64(r) * kc);
    }
    if (k == 1) {
      cblas_dgemv(CblasColMajor, CblasTrans, m, b.nscol, -1.0, L + b.nscol, ld, G, 1, 1.0, Y, 1);
    } else {
      cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, kc, b.nscol, m, -1.0, G, kc,
                  L + b.nscol, ld, 1.0, Y, k);
    }
  }
  if (k == 1) {
    cblas_dtrsv(CblasColMajor, CblasLower, CblasTrans, CblasNonUnit, b.nscol, L, ld, Y, 1);
  } else {
    // L11ᵀ Y = B ⇔ Yᵀ L11 = Bᵀ
    cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasNoTrans, CblasNonUnit, kc, b.nscol, 1.0,
                L, ld, Y, k);
  }
}

// R (n × k, row-major) ← b (n × k, column-major), in tiles of rows that stay in cache.
void columns_to_rows(const double* b, Eigen::Index n, int k, double* R) {
  constexpr Eigen::Index kTile = 64;
  for (Eigen::Index i0 = 0; i0 < n; i0 += kTile) {
    const Eigen::Index i1 = std::min(n, i0 + kTile);
    for (int j = 0; j < k; ++j) {
      const double* col = b + Int64(j) * n;
      for (Eigen::Index i = i0; i < i1; ++i) R[i * k + j] = col[i];
    }
  }
}

// x (n × k, column-major) ← R (n × k, row-major), in tiles.
void rows_to_columns(const double* R, Eigen::Index n, int k, double* x) {
  constexpr Eigen::Index kTile = 64;
  for (Eigen::Index i0 = 0; i0 < n; i0 += kTile) {
    const Eigen::Index i1 = std::min(n, i0 + kTile);
    for (int j = 0; j < k; ++j) {
      double* col = x + Int64(j) * n;
      for (Eigen::Index i = i0; i < i1; ++i) col[i] = R[i * k + j];
    }
  }
}

// The split of the elimination tree: two bins of subtrees and the serial top (ascending).
struct Split {
  std::vector<Subtree> bin[2];
  std::vector<int> top;
  std::vector<int> top_index;  // n: column → compact index among the top's columns, or −1
  int n_top = 0;
  double top_share = 0.0;
};

// The supernodal elimination tree: parent (−1 at a root) and the first supernode of each subtree;
// false when the numbering is not a postorder (every subtree a contiguous range ending at its
// root).
bool supernodal_tree(const SupernodalPattern& p, std::vector<int>& col_super,
                     std::vector<int>& parent, std::vector<int>& first) {
  const int ns = int(p.super.size()) - 1;
  col_super.resize(p.n);
  for (int s = 0; s < ns; ++s) {
    std::fill(col_super.begin() + p.super[s], col_super.begin() + p.super[s + 1], s);
  }
  parent.assign(ns, -1);
  first.resize(ns);
  std::iota(first.begin(), first.end(), 0);
  std::vector<int> size(ns, 1);
  for (int s = 0; s < ns; ++s) {
    const int nscol = p.super[s + 1] - p.super[s];
    const Int64 r0 = p.row_start[s];
    if (p.row_start[s + 1] - r0 > nscol) {
      const int q = col_super[p.rows[r0 + nscol]];
      if (q <= s) throw InvalidInput("SupernodalSolver: a supernode's parent precedes it");
      parent[s] = q;
      first[q] = std::min(first[q], first[s]);
      size[q] += size[s];
    }
  }
  for (int s = 0; s < ns; ++s) {
    if (s - first[s] + 1 != size[s]) return false;
  }
  return true;
}

// Largest bin after assigning the subtrees (heaviest first) to the lighter of two bins.
double two_bin_makespan(std::vector<int> roots, const std::vector<double>& work,
                        std::vector<int>* bin_of = nullptr) {
  std::sort(roots.begin(), roots.end(),
            [&](int a, int b) { return work[a] != work[b] ? work[a] > work[b] : a < b; });
  double load[2] = {0.0, 0.0};
  for (const int r : roots) {
    const int b = load[1] < load[0] ? 1 : 0;
    load[b] += work[r];
    if (bin_of) (*bin_of)[r] = b;
  }
  return std::max(load[0], load[1]);
}

// Splits the tree: starting from the roots, the heaviest subtree is repeatedly replaced by its
// children (its root joins the serial top); the split with the least top + largest bin wins.
Split split_tree(const SupernodalPattern& p, const std::vector<int>& parent,
                 const std::vector<int>& first) {
  const int ns = int(parent.size());
  std::vector<double> own(ns), work(ns);
  std::vector<std::vector<int>> children(ns);
  std::vector<int> cand;
  for (int s = 0; s < ns; ++s) {
    own[s] = double(p.value_start[s + 1] - p.value_start[s]);
    work[s] += own[s];
    if (parent[s] >= 0) {
      work[parent[s]] += work[s];
      children[parent[s]].push_back(s);
    } else {
      cand.push_back(s);
    }
  }
  const double total = double(p.value_start[ns]);
  std::vector<int> top, best_cand = cand, best_top;
  double top_work = 0.0, best = two_bin_makespan(cand, work);
  for (int step = 0; step < 512 && !cand.empty(); ++step) {
    const auto heaviest = std::max_element(cand.begin(), cand.end(), [&](int a, int b) {
      return work[a] != work[b] ? work[a] < work[b] : a > b;
    });
    const int s = *heaviest;
    if (work[s] < 0.01 * total) break;
    cand.erase(heaviest);
    top.push_back(s);
    top_work += own[s];
    cand.insert(cand.end(), children[s].begin(), children[s].end());
    const double cost = top_work + two_bin_makespan(cand, work);
    if (cost < best) best = cost, best_cand = cand, best_top = top;
  }
  Split split;
  std::vector<int> bin_of(ns, 0);
  two_bin_makespan(best_cand, work, &bin_of);
  std::sort(best_cand.begin(), best_cand.end());
  for (const int r : best_cand) split.bin[bin_of[r]].push_back({first[r], r, p.super[r + 1]});
  std::sort(best_top.begin(), best_top.end());
  split.top = best_top;
  split.top_index.assign(p.n, -1);
  for (const int s : best_top) {
    for (int c = p.super[s]; c < p.super[s + 1]; ++c) split.top_index[c] = split.n_top++;
    split.top_share += own[s] / total;
  }
  return split;
}

void check_pattern(const SupernodalPattern& p) {
  const std::size_t ns = p.super.size();
  const bool ok = ns >= 2 && p.row_start.size() == ns && p.value_start.size() == ns &&
                  p.perm.size() == std::size_t(p.n) && p.super.front() == 0 &&
                  p.super.back() == p.n && p.row_start.back() == Int64(p.rows.size());
  if (!ok) throw InvalidInput("SupernodalSolver: inconsistent supernodal pattern");
}

// v's storage with room for at least n elements (scratch reused between solves grows only).
template <class Vector>
auto* sized(Vector& v, std::size_t n) {
  if (v.size() < n) v.resize(n);
  return v.data();
}

// The supernodes a forward pass must visit for the nonzero rows (they and their ancestors in the
// elimination tree `parent`), ascending, into reach; false when they hold half the factor or more
// (visit all). Shared by the real and the complex kernel.
bool supernodes_reached(const SupernodalPattern& p, const std::vector<int>& col_super,
                        const std::vector<int>& parent, const char* nonzero,
                        std::vector<int>& reach) {
  const int ns = int(parent.size());
  std::vector<char> mark(ns, 0);
  Int64 work = 0;
  for (Eigen::Index i = 0; i < p.n; ++i) {
    if (!nonzero[i]) continue;
    for (int s = col_super[i]; s >= 0 && !mark[s]; s = parent[s]) {
      mark[s] = 1;
      work += p.value_start[s + 1] - p.value_start[s];
    }
    if (2 * work >= p.value_start.back()) return false;
  }
  reach.clear();
  for (int s = 0; s < ns; ++s) {
    if (mark[s]) reach.push_back(s);
  }
  return true;
}

}  // namespace

struct SupernodalSolver::Impl {
  SupernodalPattern p;
  FactorPrecision precision = FactorPrecision::kDouble;
  std::vector<double> values_d;
  std::vector<float> values_f;
  // the double values: values_d's, or adopted ones (freed by release)
  const double* dvalues = nullptr;
  std::unique_ptr<double, void (*)(void*)> adopted{nullptr, nullptr};
  int max_offdiag = 0;  // largest m = nsrow − nscol
  // row copies of at least this many values go on two threads
  static constexpr Int64 kParallelCopy = 1 << 18;
  // entries of a pass's update / gather scratch (T, G) for k right-hand sides: m × k, or all of a
  // small supernode's rows for one (backward_one's [y; g])
  std::size_t scratch_rows(int k) const {
    return std::size_t(max_offdiag) * k + std::size_t(kSmallSupernode);
  }
  std::size_t block_scratch = 0;  // single precision: the largest block (nsrow × nscol)
  std::vector<int> col_super;     // n: the supernode of each column
  std::vector<int> parent;        // #supernodes: the elimination tree's parent, −1 at a root
  bool split_tree = false;        // a postordered tree: `split` holds its bins
  Split split;
  // whether a solve of k columns runs the two bins (on two threads when run_parallel() may)
  bool two_bins(int k) const { return split_tree && p.value_start.back() * k >= kParallelEntries; }
  // Buffers of one solve: the permuted right-hand sides (W) and, per bin, the update
  // / gather rows (T), a float block converted to double (S) and the updates of the top's rows
  // (acc); grown, never shrunk, so that a solver's repeated solves allocate (and page-fault)
  // nothing.
  struct Scratch {
    HugeVector W;
    std::vector<double> T[2], S[2], acc[2];
    std::vector<char> nonzero;  // n: the rows of W a gather found nonzero
  };
  // the scratch of the last solve, reused when no other solve holds it
  mutable std::mutex workspace_mutex;
  mutable Scratch workspace;
  // solve()'s right-hand sides by rows (several columns), likewise reused
  mutable std::mutex rows_mutex;
  mutable HugeVector rows_buffer;

  template <class Real>
  Block<Real> block(const Real* values, int s) const {
    const int nscol = p.super[s + 1] - p.super[s];
    const int nsrow = int(p.row_start[s + 1] - p.row_start[s]);
    return {values + p.value_start[s], p.rows.data() + p.row_start[s], nscol, nsrow, p.super[s]};
  }

  // nonzero (n flags): which rows of W are not all zero, recorded by the gather that filled W;
  // or source_rows (k rows): column j of W is zero but in row source_rows[j]
  // shift: a rank-one term to subtract from W first (folded into the forward pass)
  template <class Real>
  void solve_permuted(const Real* values, double* W, int k, Scratch& scr, const char* nonzero,
                      const int* source_rows, const RankOne& shift) const;
  void solve_permuted(double* W, int k, Scratch& scr, const char* nonzero,
                      const int* source_rows = nullptr, const RankOne& shift = {}) const {
    if (precision == FactorPrecision::kSingle) {
      solve_permuted(values_f.data(), W, k, scr, nonzero, source_rows, shift);
    } else {
      solve_permuted(dvalues, W, k, scr, nonzero, source_rows, shift);
    }
  }
  // Per supernode, the columns whose point source (column j: row source_rows[j]) lies in its
  // subtree: a contiguous range when the columns are in the order of their rows (a subtree is a
  // range of rows); empty (begin ≥ end) where none does.
  std::vector<Columns> source_columns(const int* source_rows, int k) const;
  // W[i] ← X[perm[i]] (gather) or X[perm[i]] ← W[i], rows of k values. A gather with `nonzero`
  // (n flags) also records which rows it copied are not all zero: the forward pass's reach then
  // needs no second read of the block (a 1M × 32 block: 20 ms).
  void copy_rows(const double* from, double* to, int k, bool gather, char* nonzero = nullptr) const;
  // The supernodes a forward pass must visit for the nonzero rows (they and their ancestors),
  // ascending, when they hold less than half the factor; else empty (visit all).
  std::vector<int> forward_reach(const char* nonzero) const;
  // The forward pass over the two bins and then the top; with `cols` (per supernode), each
  // supernode on its columns only (none: skipped).
  template <class Real>
  void forward_split(const Real* values, double* W, int k, Scratch& scr,
                     const std::vector<Columns>* cols, const RankOne& shift = {}) const;
  template <class Real>
  void backward_split(const Real* values, double* W, int k, Scratch& scr) const;
  // The serial top of a split pass on two halves of the k columns side by side (independent
  // in a triangular solve; whole chunks of 8 each, the same chunks as one pass over all k), or
  // on all k at once below 16: pass(columns, T, S) with each half's own scratch.
  void top_in_column_halves(int k, Scratch& scr,
                            const std::function<void(Columns, double*, double*)>& pass) const;
};

template <class Real>
void SupernodalSolver::Impl::forward_split(const Real* values, double* W, int k, Scratch& scr,
                                           const std::vector<Columns>* cols,
                                           const RankOne& shift) const {
  auto columns = [cols, k](int s) { return cols ? (*cols)[std::size_t(s)] : Columns{0, k}; };
  std::vector<double>* acc = scr.acc;
  std::vector<std::function<void()>> jobs;
  for (int b = 0; b < 2; ++b) {
    acc[b].assign(std::size_t(split.n_top) * k, 0.0);
    jobs.emplace_back([this, values, W, k, b, acc, &scr, &columns, &shift] {
      const FlushDenormalsScope no_subnormals;
      double* T = sized(scr.T[b], scratch_rows(k));
      double* S = sized(scr.S[b], block_scratch);
      for (const Subtree& st : split.bin[b]) {
        const TopAccumulator top{acc[b].data(), split.top_index.data(), st.col_end};
        for (int s = st.first; s <= st.last; ++s) {
          const Columns c = columns(s);
          if (c.begin < c.end) forward_block(block(values, s), W, k, T, S, top, c, shift);
        }
      }
    });
  }
  run_parallel(jobs);
  // the bins' updates of the top's rows, in a fixed order (bin 0, then bin 1)
  for (const int s : split.top) {
    for (int c = p.super[s]; c < p.super[s + 1]; ++c) {
      const Int64 t = Int64(split.top_index[c]) * k;
      double* w = W + Int64(c) * k;
      for (int j = 0; j < k; ++j) w[j] = (w[j] + acc[0][t + j]) + acc[1][t + j];
    }
  }
  top_in_column_halves(k, scr, [&](Columns half, double* T, double* S) {
    for (const int s : split.top) {
      const Columns c = columns(s);
      const Columns part{std::max(c.begin, half.begin), std::min(c.end, half.end)};
      if (part.begin < part.end)
        forward_block(block(values, s), W, k, T, S, TopAccumulator{}, part, shift);
    }
  });
}

void SupernodalSolver::Impl::top_in_column_halves(
    int k, Scratch& scr, const std::function<void(Columns, double*, double*)>& pass) const {
  // whole chunks of 8 on each side; one side when the top is small (a hand-off to the other
  // thread costs more than its half: 10k faces, k = 32, 2.2 -> 2.7 ms per block of sources)
  const double top_work = split.top_share * double(p.value_start.back()) * k;
  const int mid = k < 16 || top_work < double(kParallelEntries) ? k : (k / 2 + 7) / 8 * 8;
  run_halves(mid < k, [&](int half) {
    const FlushDenormalsScope no_subnormals;
    double* T = sized(scr.T[half], scratch_rows(k));
    double* S = sized(scr.S[half], block_scratch);
    const Columns cols = half == 0 ? Columns{0, mid} : Columns{mid, k};
    if (cols.begin < cols.end) pass(cols, T, S);
  });
}

template <class Real>
void SupernodalSolver::Impl::backward_split(const Real* values, double* W, int k,
                                            Scratch& scr) const {
  top_in_column_halves(k, scr, [&](Columns half, double* G, double* S) {
    for (auto it = split.top.rbegin(); it != split.top.rend(); ++it) {
      backward_block(block(values, *it), W, k, G, S, half);
    }
  });
  std::vector<std::function<void()>> jobs;
  for (int b = 0; b < 2; ++b) {
    jobs.emplace_back([this, values, W, k, b, &scr] {
      const FlushDenormalsScope no_subnormals;
      double* Gb = sized(scr.T[b], scratch_rows(k));
      double* Sb = sized(scr.S[b], block_scratch);
      const auto& bin = split.bin[b];
      for (auto st = bin.rbegin(); st != bin.rend(); ++st) {
        for (int s = st->last; s >= st->first; --s) {
          backward_block(block(values, s), W, k, Gb, Sb, Columns{0, k});
        }
      }
    });
  }
  run_parallel(jobs);
}

std::vector<int> SupernodalSolver::Impl::forward_reach(const char* nonzero) const {
  std::vector<int> reach;
  if (!supernodes_reached(p, col_super, parent, nonzero, reach)) reach.clear();
  return reach;  // empty: a full pass
}

std::vector<Columns> SupernodalSolver::Impl::source_columns(const int* source_rows, int k) const {
  const int ns = int(parent.size());
  std::vector<Columns> cols(std::size_t(ns), Columns{k, 0});
  for (int j = 0; j < k; ++j) {
    Columns& c = cols[std::size_t(col_super[std::size_t(source_rows[j])])];
    c = {std::min(c.begin, j), std::max(c.end, j + 1)};
  }
  for (int s = 0; s < ns; ++s) {  // children before parents (a postorder)
    if (parent[s] < 0) continue;
    const Columns child = cols[std::size_t(s)];
    Columns& c = cols[std::size_t(parent[s])];
    c = {std::min(c.begin, child.begin), std::max(c.end, child.end)};
  }
  return cols;
}

template <class Real>
void SupernodalSolver::Impl::solve_permuted(const Real* values, double* W, int k, Scratch& scr,
                                            const char* nonzero, const int* source_rows,
                                            const RankOne& shift) const {
  const int ns = int(p.super.size()) - 1;
  double* T = sized(scr.T[0], scratch_rows(k));
  double* S = sized(scr.S[0], block_scratch);
  const Columns all{0, k};
  if (source_rows && !shift.rows) {
    // point sources: each supernode on the columns whose source is in its subtree (the others
    // are zero in its rows and stay zero: the same values as a full pass)
    const std::vector<Columns> cols = source_columns(source_rows, k);
    if (two_bins(k)) {
      forward_split(values, W, k, scr, &cols);
    } else {
      for (int s = 0; s < ns; ++s) {
        const Columns c = cols[std::size_t(s)];
        if (c.begin < c.end) forward_block(block(values, s), W, k, T, S, TopAccumulator{}, c);
      }
    }
  } else {
    // a sparse right-hand side (a point source) reaches only its columns' ancestors: the
    // forward pass visits those (zero rows stay zero elsewhere: the same values as a full pass)
    const std::vector<int> reach =
        nonzero && !shift.rows ? forward_reach(nonzero) : std::vector<int>{};
    if (!reach.empty()) {
      for (const int s : reach) forward_block(block(values, s), W, k, T, S, TopAccumulator{}, all);
    } else if (two_bins(k)) {
      forward_split(values, W, k, scr, nullptr, shift);
    } else {
      for (int s = 0; s < ns; ++s) {
        forward_block(block(values, s), W, k, T, S, TopAccumulator{}, all, shift);
      }
    }
  }
  if (two_bins(k)) {
    backward_split(values, W, k, scr);
  } else {
    for (int s = ns - 1; s >= 0; --s) backward_block(block(values, s), W, k, T, S, all);
  }
}

void SupernodalSolver::Impl::copy_rows(const double* from, double* to, int k, bool gather,
                                       char* nonzero) const {
  const Eigen::Index n = p.n;
  auto part = [this, from, to, k, gather, nonzero, n](int half, int halves) {
    const Eigen::Index i0 = n * half / halves, i1 = n * (half + 1) / halves;
    for (Eigen::Index i = i0; i < i1; ++i) {
      const std::size_t a = std::size_t(p.perm[std::size_t(i)]) * k, w = std::size_t(i) * k;
      if (gather) {
        std::copy_n(from + a, k, to + w);
        if (nonzero)
          nonzero[i] = !std::all_of(to + w, to + w + k, [](double x) { return x == 0.0; });
      } else {
        std::copy_n(from + w, k, to + a);
      }
    }
  };
  if (Int64(n) * k < kParallelCopy) {
    part(0, 1);
    return;
  }
  run_parallel({[&part] { part(0, 2); }, [&part] { part(1, 2); }});
}

SupernodalSolver::SupernodalSolver(SupernodalPattern pattern, const double* values,
                                   FactorPrecision precision) {
  init(std::move(pattern), values, precision, nullptr, nullptr);
}

SupernodalSolver SupernodalSolver::adopt(SupernodalPattern pattern, double* values,
                                         void (*release)(void*)) {
  if (!values || !release) throw InvalidInput("SupernodalSolver::adopt: null values or release");
  SupernodalSolver s;
  s.init(std::move(pattern), values, FactorPrecision::kDouble, values, release);
  return s;
}

void SupernodalSolver::init(SupernodalPattern pattern, const double* values,
                            FactorPrecision precision, double* owned, void (*release)(void*)) {
  check_pattern(pattern);
  impl_ = std::make_unique<Impl>();
  Impl& im = *impl_;
  im.p = std::move(pattern);
  im.precision = precision;
  const Int64 count = im.p.value_start.back();
  if (precision == FactorPrecision::kSingle) {
    im.values_f.assign(values, values + count);
  } else if (owned) {
    im.dvalues = owned;  // taken over at the end: a throw before leaves them the caller's
  } else {
    im.values_d.assign(values, values + count);
    im.dvalues = im.values_d.data();
  }
  const int ns = int(im.p.super.size()) - 1;
  for (int s = 0; s < ns; ++s) {
    const int m =
        int(im.p.row_start[s + 1] - im.p.row_start[s]) - (im.p.super[s + 1] - im.p.super[s]);
    im.max_offdiag = std::max(im.max_offdiag, m);
    if (precision == FactorPrecision::kSingle) {
      im.block_scratch = std::max<std::size_t>(
          im.block_scratch, std::size_t(im.p.value_start[s + 1] - im.p.value_start[s]));
    }
  }
  std::vector<int> first;
  const bool postordered = supernodal_tree(im.p, im.col_super, im.parent, first);
  if (postordered) {
    im.split = split_tree(im.p, im.parent, first);
    im.split_tree = true;
  }
  if (owned) im.adopted = std::unique_ptr<double, void (*)(void*)>(owned, release);
}

SupernodalSolver::~SupernodalSolver() = default;
SupernodalSolver::SupernodalSolver(SupernodalSolver&&) noexcept = default;
SupernodalSolver& SupernodalSolver::operator=(SupernodalSolver&&) noexcept = default;

void SupernodalSolver::solve(const double* b, double* x, Eigen::Index cols) const {
  const Impl& im = *impl_;
  if (cols <= 0) return;
  const Eigen::Index n = im.p.n;
  if (cols > 1) {
    // a tiled transpose to rows and back (copying a row of the column-major b entry by entry
    // spans k pages: a TLB miss on nearly every entry)
    std::unique_lock<std::mutex> lock(im.rows_mutex, std::try_to_lock);
    HugeVector own;
    HugeVector& rows = lock.owns_lock() ? im.rows_buffer : own;
    double* R = sized(rows, std::size_t(n) * std::size_t(cols));
    columns_to_rows(b, n, int(cols), R);
    solve_rows(R, cols);
    rows_to_columns(R, n, int(cols), x);
    return;
  }
  std::unique_lock<std::mutex> lock(im.workspace_mutex, std::try_to_lock);
  Impl::Scratch own;
  Impl::Scratch& scr = lock.owns_lock() ? im.workspace : own;
  double* W = sized(scr.W, std::size_t(n));
  const std::vector<int>& perm = im.p.perm;
  char* nonzero = sized(scr.nonzero, std::size_t(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    W[i] = b[perm[i]];
    nonzero[i] = W[i] != 0.0;
  }
  const FlushDenormalsScope no_subnormals;
  im.solve_permuted(W, 1, scr, nonzero);
  for (Eigen::Index i = 0; i < n; ++i) x[perm[i]] = W[i];
}

void SupernodalSolver::solve_rows(double* X, Eigen::Index cols) const {
  const Impl& im = *impl_;
  if (cols <= 0) return;
  const Eigen::Index n = im.p.n;
  const int k = int(cols);
  std::unique_lock<std::mutex> lock(im.workspace_mutex, std::try_to_lock);
  Impl::Scratch own;
  Impl::Scratch& scr = lock.owns_lock() ? im.workspace : own;
  double* W = sized(scr.W, std::size_t(n) * k);
  // whole rows in permuted order (contiguous k-value copies), two halves on two threads when
  // the block is large (a copy of 1M × 32 values is bandwidth-bound: one core's stream does not
  // saturate the memory)
  char* nonzero = sized(scr.nonzero, std::size_t(n));
  im.copy_rows(X, W, k, true, nonzero);
  const FlushDenormalsScope no_subnormals;
  im.solve_permuted(W, k, scr, nonzero);
  im.copy_rows(W, X, k, false);
}

const std::vector<int>& SupernodalSolver::permutation() const { return impl_->p.perm; }

void SupernodalSolver::solve_rows_in_factor_order(double* W, Eigen::Index cols,
                                                  const int* source_rows, const double* shift_rows,
                                                  const double* shift_sums) const {
  const Impl& im = *impl_;
  if (cols <= 0) return;
  std::unique_lock<std::mutex> lock(im.workspace_mutex, std::try_to_lock);
  Impl::Scratch own;
  Impl::Scratch& scr = lock.owns_lock() ? im.workspace : own;
  const FlushDenormalsScope no_subnormals;
  im.solve_permuted(W, int(cols), scr, nullptr, source_rows,
                    shift_rows && shift_sums ? RankOne{shift_rows, shift_sums} : RankOne{});
}

std::size_t SupernodalSolver::bytes_per_pass() const {
  const Impl& im = *impl_;
  const std::size_t value_bytes = im.precision == FactorPrecision::kSingle ? 4 : 8;
  return std::size_t(entries()) * value_bytes + im.p.rows.size() * sizeof(int);
}

std::int64_t SupernodalSolver::entries() const { return impl_->p.value_start.back(); }
bool SupernodalSolver::split(Eigen::Index cols) const { return impl_->two_bins(int(cols)); }
double SupernodalSolver::top_share() const { return impl_->split.top_share; }

// --- ComplexSupernodalSolver -------------------------------------------------------------------
// Against CHOLMOD's supernodal complex solve (zgemv/ztrsv per supernode) on the vector heat
// method's M + tL∇ of igea (268k faces), one thread, CPU seconds, medians of 7 interleaved
// (`OMP_NUM_THREADS=1 ifem_bench vector_repeat --mesh igea_268k.ply --what solves --cpu`): a point
// source 0.061 -> 0.030 s (its forward pass visits the source's ancestors only), a dense
// right-hand side 0.060 -> 0.046 s; the vector products of complex pairs below took them from
// 0.042 and 0.057 s (plain complex arithmetic per entry, not vectorized). docs/decisions.md D-109.

namespace {

// Complex values as (re, im) pairs of doubles, multiplied by hand: std::complex's operator*
// checks for infinities and NaNs on every product (__muldc3) unless the whole build takes
// -fcx-limited-range.
struct Cx {
  double re, im;
};
static_assert(sizeof(Cx) == sizeof(std::complex<double>), "Cx is std::complex<double>'s layout");

// One supernode's block: nsrow × nscol complex values, column-major; rows R; first column k1.
struct ComplexBlock {
  const Cx* L;
  const int* R;
  int nscol, nsrow, k1;
};

// Two complex values as one vector of four doubles (re, im, re, im), and the pairs swapped
// (im, re, im, re): a product of complex numbers in two vector multiplications.
using C2 = Lanes<4>::V;
[[gnu::always_inline]] inline C2 load2(const Cx* p) { return load<4>(&p->re); }
[[gnu::always_inline]] inline void store2(Cx* p, C2 v) { store<4>(&p->re, v); }
[[gnu::always_inline]] inline C2 swap_pairs(C2 v) {
#if defined(__clang__)
  return __builtin_shufflevector(v, v, 1, 0, 3, 2);
#else
  typedef long long Mask __attribute__((vector_size(32)));
  return __builtin_shuffle(v, Mask{1, 0, 3, 2});
#endif
}

// dst[i] −= a[i]·y for i < count, y = (yr, yi) given as YR = (yr, yr, yr, yr) and YI = (−yi, yi,
// −yi, yi): a·y = a·YR + swap(a)·YI; two entries per vector, the last one alone (the same
// expression).
[[gnu::always_inline]] inline void subtract_products(Cx* dst, const Cx* a, int count, C2 YR,
                                                     C2 YI) {
  int i = 0;
  for (; i + 2 <= count; i += 2) {
    const C2 l = load2(a + i);
    store2(dst + i, load2(dst + i) - (l * YR + swap_pairs(l) * YI));
  }
  if (i < count) {
    dst[i].re -= a[i].re * YR[0] + a[i].im * YI[0];
    dst[i].im -= a[i].im * YR[1] + a[i].re * YI[1];
  }
}

// Forward substitution of one supernode: y ← L11⁻¹ y (the supernode's rows of W, in place), and
// the rows below, W[R[r]] (or the bin's accumulator for rows past col_end), −= (L21 y)[r].
// T: scratch of m = nsrow − nscol entries (it collects −L21 y).
IFEM_HOST_CLONES void complex_forward_block(const ComplexBlock& b, Cx* W, Cx* T, Cx* acc,
                                            const int* top_index, int col_end) {
  const int nscol = b.nscol, nsrow = b.nsrow, m = nsrow - nscol;
  Cx* y = W + b.k1;
  for (int i = 0; i < m; ++i) T[i] = {0.0, 0.0};
  for (int j = 0; j < nscol; ++j) {
    const Cx* col = b.L + Int64(j) * nsrow;
    const double inv = 1.0 / col[j].re;  // the diagonal of L Lᴴ's factor is real
    const double yr = y[j].re * inv, yi = y[j].im * inv;
    y[j] = {yr, yi};
    const C2 YR = {yr, yr, yr, yr}, YI = {-yi, yi, -yi, yi};
    subtract_products(y + j + 1, col + j + 1, nscol - j - 1, YR, YI);
    subtract_products(T, col + nscol, m, YR, YI);
  }
  const int* rows = b.R + nscol;
  for (int r = 0; r < m; ++r) {
    const int i = rows[r];
    Cx& dst = acc && i >= col_end ? acc[top_index[i]] : W[i];
    dst.re += T[r].re;
    dst.im += T[r].im;
  }
}

// Backward substitution of one supernode: y ← L11⁻ᴴ (y − L21ᴴ g), g the (final) rows below;
// Z: scratch of nsrow entries, [y; g], so that each column is one conjugated dot product:
// Σ conj(l)·z has real part Σ (l·z) over all lanes and imaginary part the alternating sum of
// l·swap(z), in two independent pairs of vector sums (a fixed order).
IFEM_HOST_CLONES void complex_backward_block(const ComplexBlock& b, Cx* W, Cx* Z) {
  const int nscol = b.nscol, nsrow = b.nsrow;
  Cx* y = W + b.k1;
  std::copy(y, y + nscol, Z);
  const int* rows = b.R;
  for (int r = nscol; r < nsrow; ++r) Z[r] = W[rows[r]];
  for (int j = nscol - 1; j >= 0; --j) {
    const Cx* col = b.L + Int64(j) * nsrow;
    C2 p0 = {0.0, 0.0, 0.0, 0.0}, q0 = p0, p1 = p0, q1 = p0;
    int i = j + 1;
    for (; i + 4 <= nsrow; i += 4) {
      const C2 l0 = load2(col + i), z0 = load2(Z + i);
      const C2 l1 = load2(col + i + 2), z1 = load2(Z + i + 2);
      p0 += l0 * z0;
      q0 += l0 * swap_pairs(z0);
      p1 += l1 * z1;
      q1 += l1 * swap_pairs(z1);
    }
    if (i + 2 <= nsrow) {
      const C2 l0 = load2(col + i), z0 = load2(Z + i);
      p0 += l0 * z0;
      q0 += l0 * swap_pairs(z0);
      i += 2;
    }
    const C2 p = p0 + p1, q = q0 + q1;
    double re = (p[0] + p[1]) + (p[2] + p[3]);
    double im = (q[0] - q[1]) + (q[2] - q[3]);
    if (i < nsrow) {
      re += col[i].re * Z[i].re + col[i].im * Z[i].im;
      im += col[i].re * Z[i].im - col[i].im * Z[i].re;
    }
    const double inv = 1.0 / col[j].re;
    Z[j] = {(Z[j].re - re) * inv, (Z[j].im - im) * inv};
  }
  std::copy(Z, Z + nscol, y);
}

}  // namespace

struct ComplexSupernodalSolver::Impl {
  SupernodalPattern p;
  const Cx* values = nullptr;
  int max_rows = 0;            // largest nsrow
  std::vector<int> col_super;  // n: the supernode of each column
  std::vector<int> parent;     // #supernodes: the elimination tree's parent, −1 at a root
  bool split_tree = false;
  Split split;
  bool two_bins() const {
    return split_tree && 2 * p.value_start.back() >= SupernodalSolver::kParallelEntries;
  }
  struct Scratch {
    std::vector<Cx> W, T[2], acc[2];
    std::vector<char> nonzero;
    std::vector<int> reach;
  };
  mutable std::mutex workspace_mutex;
  mutable Scratch workspace;

  ComplexBlock block(int s) const {
    return {values + p.value_start[s], p.rows.data() + p.row_start[s], p.super[s + 1] - p.super[s],
            int(p.row_start[s + 1] - p.row_start[s]), p.super[s]};
  }
  // The supernodes the forward pass visits for the nonzero rows (they and their ancestors,
  // ascending) into reach; false when they hold half the factor or more (visit all).
  bool forward_reach(const char* nonzero, std::vector<int>& reach) const;
  void solve_permuted(Cx* W, Scratch& scr, const char* nonzero) const;
};

bool ComplexSupernodalSolver::Impl::forward_reach(const char* nonzero,
                                                  std::vector<int>& reach) const {
  return supernodes_reached(p, col_super, parent, nonzero, reach);
}

void ComplexSupernodalSolver::Impl::solve_permuted(Cx* W, Scratch& scr, const char* nonzero) const {
  const int ns = int(p.super.size()) - 1;
  const std::size_t rows = std::size_t(max_rows);
  Cx* T = sized(scr.T[0], rows);
  const bool bins = two_bins();
  if (forward_reach(nonzero, scr.reach)) {
    for (const int s : scr.reach) complex_forward_block(block(s), W, T, nullptr, nullptr, 0);
  } else if (bins) {
    std::vector<std::function<void()>> jobs;
    for (int b = 0; b < 2; ++b) {
      scr.acc[b].assign(std::size_t(split.n_top), Cx{0.0, 0.0});
      Cx* Tb = sized(scr.T[b], rows);
      jobs.emplace_back([this, W, Tb, b, &scr] {
        const FlushDenormalsScope no_subnormals;
        for (const Subtree& st : split.bin[b]) {
          for (int s = st.first; s <= st.last; ++s) {
            complex_forward_block(block(s), W, Tb, scr.acc[b].data(), split.top_index.data(),
                                  st.col_end);
          }
        }
      });
    }
    run_parallel(jobs);
    for (const int s : split.top) {  // the bins' updates of the top's rows: bin 0, then bin 1
      for (int c = p.super[s]; c < p.super[s + 1]; ++c) {
        const Cx a0 = scr.acc[0][std::size_t(split.top_index[c])];
        const Cx a1 = scr.acc[1][std::size_t(split.top_index[c])];
        W[c] = {(W[c].re + a0.re) + a1.re, (W[c].im + a0.im) + a1.im};
      }
    }
    for (const int s : split.top) complex_forward_block(block(s), W, T, nullptr, nullptr, 0);
  } else {
    for (int s = 0; s < ns; ++s) complex_forward_block(block(s), W, T, nullptr, nullptr, 0);
  }
  if (!bins) {
    for (int s = ns - 1; s >= 0; --s) complex_backward_block(block(s), W, T);
    return;
  }
  // the top from its root down, then the two bins side by side: a bin reads its own rows and
  // the top's (final by then) and writes its own
  for (auto it = split.top.rbegin(); it != split.top.rend(); ++it) {
    complex_backward_block(block(*it), W, T);
  }
  std::vector<std::function<void()>> jobs;
  for (int b = 0; b < 2; ++b) {
    Cx* Zb = sized(scr.T[b], rows);
    jobs.emplace_back([this, W, Zb, b] {
      const FlushDenormalsScope no_subnormals;
      const auto& bin = split.bin[b];
      for (auto st = bin.rbegin(); st != bin.rend(); ++st) {
        for (int s = st->last; s >= st->first; --s) complex_backward_block(block(s), W, Zb);
      }
    });
  }
  run_parallel(jobs);
}

ComplexSupernodalSolver::ComplexSupernodalSolver(SupernodalPattern pattern,
                                                 const std::complex<double>* values)
    : impl_(std::make_unique<Impl>()) {
  check_pattern(pattern);
  Impl& im = *impl_;
  im.p = std::move(pattern);
  im.values = reinterpret_cast<const Cx*>(values);
  const int ns = int(im.p.super.size()) - 1;
  for (int s = 0; s < ns; ++s) {
    im.max_rows = std::max(im.max_rows, int(im.p.row_start[s + 1] - im.p.row_start[s]));
  }
  std::vector<int> first;
  if (supernodal_tree(im.p, im.col_super, im.parent, first)) {
    im.split = split_tree(im.p, im.parent, first);
    im.split_tree = true;
  }
}

ComplexSupernodalSolver::~ComplexSupernodalSolver() = default;
ComplexSupernodalSolver::ComplexSupernodalSolver(ComplexSupernodalSolver&&) noexcept = default;
ComplexSupernodalSolver& ComplexSupernodalSolver::operator=(ComplexSupernodalSolver&&) noexcept =
    default;

void ComplexSupernodalSolver::solve(const std::complex<double>* b, std::complex<double>* x,
                                    Eigen::Index cols) const {
  const Impl& im = *impl_;
  const Eigen::Index n = im.p.n;
  std::unique_lock<std::mutex> lock(im.workspace_mutex, std::try_to_lock);
  Impl::Scratch own;
  Impl::Scratch& scr = lock.owns_lock() ? im.workspace : own;
  Cx* W = sized(scr.W, std::size_t(n));
  char* nonzero = sized(scr.nonzero, std::size_t(n));
  const std::vector<int>& perm = im.p.perm;
  const FlushDenormalsScope no_subnormals;
  for (Eigen::Index j = 0; j < cols; ++j) {
    const Cx* bj = reinterpret_cast<const Cx*>(b) + j * n;
    for (Eigen::Index i = 0; i < n; ++i) {
      W[i] = bj[perm[i]];
      nonzero[i] = W[i].re != 0.0 || W[i].im != 0.0;
    }
    im.solve_permuted(W, scr, nonzero);
    Cx* xj = reinterpret_cast<Cx*>(x) + j * n;
    for (Eigen::Index i = 0; i < n; ++i) xj[perm[i]] = W[i];
  }
}

std::size_t ComplexSupernodalSolver::bytes_per_pass() const {
  const Impl& im = *impl_;
  return std::size_t(im.p.value_start.back()) * sizeof(Cx) + im.p.rows.size() * sizeof(int);
}

bool ComplexSupernodalSolver::split() const { return impl_->two_bins(); }

}  // namespace ifem::solvers
