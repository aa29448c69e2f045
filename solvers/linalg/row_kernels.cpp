#include "solvers/linalg/row_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "solvers/linalg/lanes.h"

namespace ifem::solvers {

// Why hand-written vectors here (GCC vector extensions, each function compiled for AVX-512,
// AVX2 + FMA and the baseline by IFEM_HOST_CLONES, no ISA builtins): the library is built for
// baseline x86-64 (SSE2: two doubles per vector), and these loops are the heat method's
// block steps whose times were measured against plainer forms (docs/decisions.md, "Blocks of
// sources, sessions 12-14"): the row divergence is bounded by its square roots and its corner
// rows' cache misses (prefetching them: 1M faces, a block of 32, 90 -> 63 ms), and GCC 12 turned
// a vector comparison used as a value into a compare and branch per lane (hence the integer
// masks below); the output's transpose took 15 ms value by value at 1M faces (rows_to_output).
// Not re-measured against plain `#pragma omp simd` loops in issue 28 (only the AVX-512 rsqrt14
// builtin variant was dropped: see inverse_sqrt()).

namespace {

using lanes::FloatLanes;
using lanes::IntLanes;
using lanes::Lanes;

// 1/√q for C lanes of q in [2⁻¹⁰², 32) (a normalized squared length), to ~2e-14 relative or
// better: a float square root and division (half-width lanes, short latency) and one Newton
// step in double, which squares float's relative error (~1e-7 → ~2e-14). The divider, not
// memory, bounded the row divergence with double sqrt and division. The same arithmetic for
// every C, so a column's bits do not depend on the chunk it falls in. (An AVX-512 variant with
// vrsqrt14pd took a 1M-face block of 32 from 47 to 41 ms, ~1.5 % of that block's query, on
// hosts with AVX-512 only: dropped with the other ISA builtins, issue 28.)
template <int C>
[[gnu::always_inline]] inline typename Lanes<C>::V inverse_sqrt(typename Lanes<C>::V q) {
  using V = typename Lanes<C>::V;
  const V half_q = 0.5 * q;
  V r0;
  if constexpr (C == 1) {
    r0 = double(1.0f / std::sqrt(float(q)));
  } else {
    using F = typename FloatLanes<C>::F;
    F qf = __builtin_convertvector(q, F);
    for (int c = 0; c < C; ++c) qf[c] = std::sqrt(qf[c]);
    r0 = __builtin_convertvector(1.0f / qf, V);
  }
  return r0 * (1.5 - half_q * (r0 * r0));
}

// 2^(1023 − e) for the biased exponent e of each lane of m (at least 2⁻¹⁰²²), from m's bits mb:
// m times it is in [1, 2) for a normal m, in [2, 4) for m ≥ 2¹⁰²³ and in [2⁻⁵¹, 2) for a
// subnormal one. An exact scaling by a power of two instead of a division by m.
template <int C>
[[gnu::always_inline]] inline typename Lanes<C>::V power_of_two_scale(typename IntLanes<C>::I mb) {
  using I = typename IntLanes<C>::I;
  I b = 2046 - ((mb >> 52) & 0x7ff);
  b = b < 1 ? b - b + 1 : b;
  return lanes::bit_cast<typename Lanes<C>::V>(b << 52);
}

// All ones where 0 < mb < +∞'s bits (mb: a double's bits as int64), else 0, with no comparison:
// u = mb − 1 (unsigned) is below 2⁶³ − c exactly when neither u nor u + c has its top bit set.
template <int C>
[[gnu::always_inline]] inline typename IntLanes<C>::I nonzero_finite_mask(
    typename IntLanes<C>::I mb) {
  using I = typename IntLanes<C>::I;
  using U = typename IntLanes<C>::U;
  constexpr std::uint64_t kInfBits = 0x7ff0000000000000u;
  constexpr std::uint64_t c = (std::uint64_t(1) << 63) - (kInfBits - 1);
  const U u = lanes::bit_cast<U>(mb) - 1u;
  return lanes::bit_cast<I>(((u | (u + c)) >> 63) - 1u);
}

// a where the lanes of `mask` are set (all bits), else 0: a bitwise and (a vector ternary made
// GCC test and branch lane by lane).
template <int C, class Mask>
[[gnu::always_inline]] inline typename Lanes<C>::V where(Mask mask, typename Lanes<C>::V a) {
  return lanes::bit_cast<typename Lanes<C>::V>(lanes::bit_cast<Mask>(a) & mask);
}

// unit_corners() for C columns of a row-major block at once: the face's corners' rows u0, u1,
// u2 (C values each) add their contributions to the rows d0, d1, d2; lanes where ∇u is 0 or not
// finite add 0. unit_corners()'s formula with v scaled by a power of two (not divided by its
// largest component) and normalized by inverse_sqrt(): equal to ~2e-14 relative.
template <int C>
[[gnu::always_inline]] inline void unit_corners_lanes(const double* fr, const double* const u[3],
                                                      double* const d[3], double half_s) {
  using V = typename Lanes<C>::V;
  const double l0 = fr[0], x = fr[1], y = fr[2];
  const V u0 = lanes::load<C>(u[0]), u1 = lanes::load<C>(u[1]), u2 = lanes::load<C>(u[2]);
  const V vx = y * (u1 - u0);
  const V vy = x * (u0 - u1) + l0 * (u2 - u0);
  // |vx|, |vy| by clearing the sign bit (one and; a comparison made GCC compare and blend)
  using U = typename IntLanes<C>::U;
  constexpr std::uint64_t kNoSign = ~(std::uint64_t(1) << 63);
  const V ax = lanes::bit_cast<V>(lanes::bit_cast<U>(vx) & kNoSign);
  const V ay = lanes::bit_cast<V>(lanes::bit_cast<U>(vy) & kNoSign);
  const V m = ax > ay ? ax : ay;
  // ∇u nonzero and finite: m's bits (m ≥ 0, or a NaN of either sign) strictly between 0 and
  // +∞'s, as an all-ones / zero mask by integer arithmetic (GCC 12 turned a vector comparison used
  // as a value into a compare and branch per lane)
  using I = typename IntLanes<C>::I;
  const I mb = lanes::bit_cast<I>(m);
  const I ok = nonzero_finite_mask<C>(mb);
  const V scale = power_of_two_scale<C>(mb);
  const V nx = vx * scale, ny = vy * scale;
  // the corners' terms of −n/|n| (unit_corners()) as linear forms in n times 1/|n|: the forms
  // are computed while the square root is, so the chain the loop waits on is one product shorter
  const V r = inverse_sqrt<C>(nx * nx + ny * ny);
  const V p0 = (y * half_s) * nx - ((x - l0) * half_s) * ny;
  const V p1 = (x * half_s) * ny - (y * half_s) * nx;
  const V p2 = (-l0 * half_s) * ny;
  lanes::store<C>(d[0], lanes::load<C>(d[0]) + where<C>(ok, p0 * r));
  lanes::store<C>(d[1], lanes::load<C>(d[1]) + where<C>(ok, p1 * r));
  lanes::store<C>(d[2], lanes::load<C>(d[2]) + where<C>(ok, p2 * r));
}

// unit_corners_lanes() on columns [j, j + C) of the rows u and d.
template <int C>
[[gnu::always_inline]] inline void unit_corners_at(const double* fr, const double* const u[3],
                                                   double* const d[3], Index j, double half_s) {
  const double* uj[3] = {u[0] + j, u[1] + j, u[2] + j};
  double* dj[3] = {d[0] + j, d[1] + j, d[2] + j};
  unit_corners_lanes<C>(fr, uj, dj, half_s);
}

}  // namespace

// faces in order, chunks of 8, 4, 2, 1 columns
IFEM_HOST_CLONES void unit_divergence_rows(const double* frame, const Index* tail, Index nf,
                                           const double* U, const Index* u_row, const Index* d_row,
                                           Index k, Index j0, Index j1, double half_s,
                                           double* div) {
  // the row of U that holds vertex v's values: v, or u_row[v]
  auto at = [U, u_row, k](Index v) { return U + std::int64_t(u_row ? u_row[v] : v) * k; };
  auto dt = [div, d_row, k](Index v) { return div + std::int64_t(d_row ? d_row[v] : v) * k; };
  // the rows of the face kFacesAhead faces on are asked for now (lanes::prefetch): a face's
  // corners are rows far apart in the block, and waiting on them bounded this loop (1M faces,
  // block of 32: 90 → 63 ms; docs/decisions.md, "Blocks of sources, session 13")
  constexpr Index kFacesAhead = 8;
  for (Index f = 0; f < nf; ++f) {
    if (f + kFacesAhead < nf) {
      const Index* ta = tail + 3 * (f + kFacesAhead);
      for (int q = 0; q < 3; ++q) {
        lanes::prefetch(at(ta[q]) + j0, j1 - j0);
        lanes::prefetch<true>(dt(ta[q]) + j0, j1 - j0);
      }
    }
    const double* fr = frame + 3 * f;
    if (!(fr[2] > 0.0)) continue;
    const Index* t = tail + 3 * f;
    const double* u[3] = {at(t[0]), at(t[1]), at(t[2])};
    double* d[3] = {dt(t[0]), dt(t[1]), dt(t[2])};
    Index j = j0;
    for (; j + 8 <= j1; j += 8) unit_corners_at<8>(fr, u, d, j, half_s);
    if (j + 4 <= j1) unit_corners_at<4>(fr, u, d, j, half_s), j += 4;
    if (j + 2 <= j1) unit_corners_at<2>(fr, u, d, j, half_s), j += 2;
    if (j < j1) unit_corners_at<1>(fr, u, d, j, half_s);
  }
}

// Columns [0, k) of rows [v0, v1) of a row-major block H: per column the largest finite value
// (into hx) and the smallest, NaN once any value is NaN (into hn), over the rows whose label is
// `comp` (every row when label is null). Branch-free per column: vectorized, for the host's
// widest vectors.
IFEM_HOST_CLONES void extremes_of_rows(const double* H, Index v0, Index v1, std::int64_t k,
                                       const Index* label, Index comp, double* __restrict hx,
                                       double* __restrict hn) {
  constexpr double kMax = std::numeric_limits<double>::max();
  for (Index v = v0; v < v1; ++v) {
    if (label && label[v] != comp) continue;
    const double* __restrict h = H + v * k;
    for (std::int64_t j = 0; j < k; ++j) {
      const double x = h[j];
      hx[j] = x > hx[j] && x <= kMax ? x : hx[j];
      hn[j] = x < hn[j] || x != x ? x : hn[j];
    }
  }
}

// out[j][v] = max(P[row[v]·k + j] − shift[j], 0)·scale for the vertices [t0, t1) and the k
// columns: blocks of 8 vertices × 8 columns (8 rows' values loaded as vectors, clamped and
// scaled, transposed in registers, stored as 8 consecutive values of each column), the rest one
// value at a time. The same operations on every value as the scalar loop, so the same bits
// (NaN stays NaN, −0 stays −0). Value by value, the output's transpose of a 1M-face block of 32
// sources took 15 ms.
IFEM_HOST_CLONES void rows_to_output(const double* P, const Index* row, Index t0, Index t1,
                                     std::int64_t k, const double* shift, double scale,
                                     double* const* out) {
  using V = lanes::Lanes<8>::V;
  using I = lanes::IntLanes<8>::I;
  auto value = [&](Index v, std::int64_t j) {
    out[j][v] = std::max(P[row[v] * k + j] - shift[j], 0.0) * scale;
  };
  const std::int64_t k8 = k / 8 * 8;
  Index v = t0;
  for (; v + 8 <= t1; v += 8) {
    for (std::int64_t c = 0; c < k8; c += 8) {
      const V sh = lanes::load<8>(shift + c);
      V r[8];
      for (int i = 0; i < 8; ++i) {
        const V d = lanes::load<8>(P + std::int64_t(row[v + i]) * k + c) - sh;
        const I negative = d < V{};
        r[i] = lanes::bit_cast<V>(lanes::bit_cast<I>(d) & ~negative) * scale;
      }
      // 8 × 8 transpose: pairs of rows, pairs of pairs, halves
      V a[8], b[8];
      for (int p = 0; p < 8; p += 2) {
        a[p] = __builtin_shufflevector(r[p], r[p + 1], 0, 8, 2, 10, 4, 12, 6, 14);
        a[p + 1] = __builtin_shufflevector(r[p], r[p + 1], 1, 9, 3, 11, 5, 13, 7, 15);
      }
      for (int q = 0; q < 8; q += 4) {
        for (int e = 0; e < 2; ++e) {
          b[q + e] = __builtin_shufflevector(a[q + e], a[q + e + 2], 0, 1, 8, 9, 4, 5, 12, 13);
          b[q + e + 2] =
              __builtin_shufflevector(a[q + e], a[q + e + 2], 2, 3, 10, 11, 6, 7, 14, 15);
        }
      }
      for (int q = 0; q < 4; ++q) {
        lanes::store<8>(out[c + q] + v,
                        __builtin_shufflevector(b[q], b[q + 4], 0, 1, 2, 3, 8, 9, 10, 11));
        lanes::store<8>(out[c + q + 4] + v,
                        __builtin_shufflevector(b[q], b[q + 4], 4, 5, 6, 7, 12, 13, 14, 15));
      }
    }
    for (std::int64_t j = k8; j < k; ++j) {
      for (Index i = v; i < v + 8; ++i) value(i, j);
    }
  }
  for (; v < t1; ++v) {
    for (std::int64_t j = 0; j < k; ++j) value(v, j);
  }
}

}  // namespace ifem::solvers
