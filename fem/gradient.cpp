#include "fem/gradient.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>  // declares the AVX-512 builtins (rsqrt14 below)
#endif

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/lanes.h"
#include "intrinsic/core/parallel.h"

namespace ifem::fem {

using intrinsic::IntrinsicTriangulation;

namespace {

// OpenMP regions below this many faces run serially: on a busy machine, waking a thread costs
// up to a scheduler time slice (milliseconds), more than the whole loop on a small mesh.
constexpr Index kParallelFaces = 20000;

// Layout of face f: corner positions p0 = 0, p1 = (l0, 0), p2 = (x, y); area A.
struct Layout {
  double l0, x, y, area;
};

Layout layout(const IntrinsicTriangulation& tri, Index f) {
  const double l0 = tri.halfedge_length(3 * f);      // corner 0 → 1
  const double l1 = tri.halfedge_length(3 * f + 1);  // corner 1 → 2
  const double l2 = tri.halfedge_length(3 * f + 2);  // corner 2 → 0
  const double area = intrinsic::triangle_area(l0, l1, l2);
  Layout L{l0, 0.0, 0.0, area};
  if (l0 > 0.0) {
    const Eigen::Vector2d apex = intrinsic::triangle_apex(l0, l1, l2);
    L.x = apex.x();
    L.y = apex.y();  // stable from Heron, never NaN
  }
  return L;
}

// Gradients of the three hat functions on a laid-out face: ∇φ_i = J·e_i / (2A) where J rotates
// the opposite side by 90°. Returns false on a degenerate face.
bool hat_gradients(const Layout& L, Eigen::Vector2d g[3]) {
  if (!(L.area > 0.0)) return false;
  const Eigen::Vector2d p[3] = {{0.0, 0.0}, {L.l0, 0.0}, {L.x, L.y}};
  const double inv2a = 1.0 / (2.0 * L.area);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d e = p[(i + 2) % 3] - p[(i + 1) % 3];  // opposite side, ccw
    g[i] = Eigen::Vector2d(-e.y(), e.x()) * inv2a;
  }
  return true;
}

// x ← −x/|x|, |x| scaled by its largest component first (as hypot, so gradients of ~1e-200
// from underflowing heat still normalize, at a fraction of libm hypot's cost: it was the
// largest single item of a heat query). False, x untouched, when |x| is 0 or not finite.
bool negate_normalize(Eigen::Vector2d& x) {
  const double m = std::max(std::abs(x.x()), std::abs(x.y()));
  if (!(m > 0.0) || !std::isfinite(m)) return false;
  const Eigen::Vector2d y = x / m;
  x = y / -std::sqrt(y.squaredNorm());
  return true;
}

}  // namespace

Eigen::Vector2d face_corner2(const IntrinsicTriangulation& tri, Index f) {
  const Layout L = layout(tri, f);
  return {L.x, L.y};
}

Eigen::MatrixX2d gradient(const IntrinsicTriangulation& tri, const Eigen::VectorXd& u) {
  if (u.size() != tri.n_vertices()) {
    throw InvalidInput("gradient: u has " + std::to_string(u.size()) +
                       " values, expected #V = " + std::to_string(tri.n_vertices()));
  }
  const Index nf = tri.n_faces();
  Eigen::MatrixX2d G(nf, 2);
  const auto& tail = tri.tails();
#pragma omp parallel for schedule(static) if (nf >= kParallelFaces)
  for (Index f = 0; f < nf; ++f) {
    Eigen::Vector2d g[3];
    if (!hat_gradients(layout(tri, f), g)) {
      G.row(f).setZero();
      continue;
    }
    const Eigen::Vector2d v =
        u[tail[3 * f]] * g[0] + u[tail[3 * f + 1]] * g[1] + u[tail[3 * f + 2]] * g[2];
    G.row(f) = v.transpose();
  }
  return G;
}

Eigen::VectorXd divergence(const IntrinsicTriangulation& tri, const Eigen::MatrixX2d& X) {
  if (X.rows() != tri.n_faces()) {
    throw InvalidInput("divergence: X has " + std::to_string(X.rows()) +
                       " rows, expected #F = " + std::to_string(tri.n_faces()));
  }
  const Index nf = tri.n_faces();
  // per-corner contributions computed in parallel, scattered serially (no atomics)
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> c(nf, 3);
  const double s = 1.0 / tri.multiplicity();
#pragma omp parallel for schedule(static) if (nf >= kParallelFaces)
  for (Index f = 0; f < nf; ++f) {
    const Layout L = layout(tri, f);
    Eigen::Vector2d g[3];
    if (!hat_gradients(L, g)) {
      c.row(f).setZero();
      continue;
    }
    const Eigen::Vector2d x = X.row(f).transpose();
    for (int i = 0; i < 3; ++i) c(f, i) = s * L.area * g[i].dot(x);
  }
  Eigen::VectorXd div = Eigen::VectorXd::Zero(tri.n_vertices());
  const auto& tail = tri.tails();
  for (Index f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) div[tail[3 * f + i]] += c(f, i);
  }
  return div;
}

Eigen::VectorXd divergence_of_unit_gradient(const IntrinsicTriangulation& tri,
                                            const Eigen::VectorXd& u,
                                            const std::vector<char>* use_face) {
  return UnitGradientDivergence(tri).apply(u, use_face);
}

Eigen::MatrixXd divergence_of_unit_gradients(const IntrinsicTriangulation& tri,
                                             const Eigen::MatrixXd& U,
                                             const std::vector<std::vector<char>>& use_face) {
  return UnitGradientDivergence(tri).apply_columns(U, use_face);
}

UnitGradientDivergence::UnitGradientDivergence(const IntrinsicTriangulation& tri)
    : n_vertices_(tri.n_vertices()),
      n_faces_(tri.n_faces()),
      scale_(1.0 / tri.multiplicity()),
      tail_(tri.tails().begin(), tri.tails().end()),
      frame_(3 * std::size_t(tri.n_faces())) {
  const Index nf = n_faces_;
#pragma omp parallel for schedule(static) if (parallel_pays(nf, kParallelFaces))
  for (Index f = 0; f < nf; ++f) {
    const Layout L = layout(tri, f);
    const bool ok = L.area > 0.0 && L.y > 0.0;
    double* fr = &frame_[3 * std::size_t(f)];
    fr[0] = L.l0;
    fr[1] = L.x;
    fr[2] = ok ? L.y : 0.0;
  }
}

namespace {

// The corner contributions c of one face (frame fr = ℓ₀, x, y) to the divergence of −∇u/|∇u|,
// u at its corners; false (c untouched) on a degenerate face or where ∇u is 0 or not finite.
bool unit_corners(const double* fr, double u0, double u1, double u2, double half_s, double c[3]) {
  const double l0 = fr[0], x = fr[1], y = fr[2];
  if (!(y > 0.0)) return false;
  // J e_0 = (−y, x − ℓ₀), J e_1 = (y, −x), J e_2 = (0, ℓ₀); v = Σ u_i J e_i = 2A ∇u
  Eigen::Vector2d v(y * (u1 - u0), x * (u0 - u1) + l0 * (u2 - u0));
  if (!negate_normalize(v)) return false;
  c[0] = half_s * (-y * v.x() + (x - l0) * v.y());
  c[1] = half_s * (y * v.x() - x * v.y());
  c[2] = half_s * (l0 * v.y());
  return true;
}

}  // namespace

Eigen::VectorXd UnitGradientDivergence::apply(const Eigen::VectorXd& u,
                                              const std::vector<char>* use_face) const {
  if (u.size() != n_vertices_) {
    throw InvalidInput("divergence_of_unit_gradient: u has " + std::to_string(u.size()) +
                       " values, expected #V = " + std::to_string(n_vertices_));
  }
  const Index nf = n_faces_;
  if (use_face && static_cast<Index>(use_face->size()) != nf) {
    throw InvalidInput("divergence_of_unit_gradient: use_face has " +
                       std::to_string(use_face->size()) +
                       " entries, expected #F = " + std::to_string(nf));
  }
  // two fixed halves of the faces, each summed in face order into its own vector, then added:
  // the same bits whether one thread or two run them
  Eigen::VectorXd half[2] = {Eigen::VectorXd::Zero(n_vertices_), Eigen::VectorXd::Zero(0)};
  const double half_s = 0.5 * scale_;
  const bool two = parallel_pays(nf, kParallelFaces);
  if (nf >= kParallelFaces) half[1] = Eigen::VectorXd::Zero(n_vertices_);
  const int parts = nf >= kParallelFaces ? 2 : 1;
#pragma omp parallel for schedule(static, 1) num_threads(2) if (two)
  for (int part = 0; part < parts; ++part) {
    double* div = half[part].data();
    const Index f1 = nf * part / parts, f2 = nf * (part + 1) / parts;
    for (Index f = f1; f < f2; ++f) {
      if (use_face && !(*use_face)[std::size_t(f)]) continue;
      const Index* t = &tail_[3 * std::size_t(f)];
      double c[3];
      if (!unit_corners(&frame_[3 * std::size_t(f)], u[t[0]], u[t[1]], u[t[2]], half_s, c)) {
        continue;
      }
      div[t[0]] += c[0];
      div[t[1]] += c[1];
      div[t[2]] += c[2];
    }
  }
  if (parts == 2) half[0] += half[1];
  return half[0];
}

Eigen::MatrixXd UnitGradientDivergence::apply_columns(
    const Eigen::MatrixXd& U, const std::vector<std::vector<char>>& use_face) const {
  Eigen::MatrixXd div(n_vertices_, U.cols());
  apply_columns(U, use_face, div);
  return div;
}

void UnitGradientDivergence::apply_columns(const Eigen::Ref<const Eigen::MatrixXd>& U,
                                           const std::vector<std::vector<char>>& use_face,
                                           Eigen::Ref<Eigen::MatrixXd> div) const {
  const Index nv = n_vertices_, nf = n_faces_;
  const Eigen::Index k = U.cols();
  if (U.rows() != nv) {
    throw InvalidInput("divergence_of_unit_gradients: U has " + std::to_string(U.rows()) +
                       " rows, expected #V = " + std::to_string(nv));
  }
  bool sizes_ok = use_face.empty() || Eigen::Index(use_face.size()) == k;
  for (const auto& mask : use_face) sizes_ok = sizes_ok && Index(mask.size()) == nf;
  if (!sizes_ok) {
    throw InvalidInput(
        "divergence_of_unit_gradients: use_face must be empty or U.cols() masks "
        "of #F = " +
        std::to_string(nf) + " entries");
  }
  if (div.rows() != nv || div.cols() != k) {
    throw InvalidInput("divergence_of_unit_gradients: the output is not #V × U.cols()");
  }
  // Threads split the columns, each summing its own columns of div in face order (no atomics);
  // faces go in tiles that stay in cache while every column of the thread reads them, and the
  // columns are read and written where they lie (a vertex-major copy made the k values of a
  // vertex contiguous but every corner a cache miss: 3× slower at 29 columns).
  div.setZero();
  const double half_s = 0.5 * scale_;
  constexpr Index kTile = 4096;
#pragma omp parallel if (k > 1 && parallel_pays(nf, kParallelFaces))
  {
#ifdef _OPENMP
    const Eigen::Index nt = omp_get_num_threads(), t = omp_get_thread_num();
#else
    const Eigen::Index nt = 1, t = 0;
#endif
    const Eigen::Index j0 = k * t / nt, j1 = k * (t + 1) / nt;
    for (Index f0 = 0; f0 < nf && j0 < j1; f0 += kTile) {
      const Index f1 = std::min(nf, f0 + kTile);
      for (Eigen::Index j = j0; j < j1; ++j) {
        const double* u = U.col(j).data();
        double* d = div.col(j).data();
        const char* use = use_face.empty() ? nullptr : use_face[std::size_t(j)].data();
        for (Index f = f0; f < f1; ++f) {
          if (use && !use[f]) continue;
          const Index* tf = &tail_[3 * std::size_t(f)];
          double cf[3];
          if (!unit_corners(&frame_[3 * std::size_t(f)], u[tf[0]], u[tf[1]], u[tf[2]], half_s,
                            cf)) {
            continue;
          }
          d[tf[0]] += cf[0];
          d[tf[1]] += cf[1];
          d[tf[2]] += cf[2];
        }
      }
    }
  }
}

namespace {

using lanes::FloatLanes;
using lanes::IntLanes;
using lanes::Lanes;

// Whether this build can run the row divergence's AVX-512 variant: GCC on x86-64, where a
// target builtin in an always-inline template is checked once the template is inlined into
// a function compiled for that target (Clang checks it in the template and refuses).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define IFEM_RSQRT14 1
#else
#define IFEM_RSQRT14 0
#endif

#if IFEM_RSQRT14
// AVX-512's vrsqrt14pd on C lanes: 1/√q to a relative 2⁻¹⁴. Only in functions compiled for
// x86-64-v4 (unit_divergence_rows_avx512).
template <int C>
[[gnu::always_inline]] inline typename Lanes<C>::V rsqrt14(typename Lanes<C>::V q) {
  using V = typename Lanes<C>::V;
  if constexpr (C == 8) {
    return __builtin_ia32_rsqrt14pd512_mask(q, V{}, 0xff);
  } else if constexpr (C == 4) {
    return __builtin_ia32_rsqrt14pd256_mask(q, V{}, 0xf);
  } else if constexpr (C == 2) {
    return __builtin_ia32_rsqrt14pd128_mask(q, V{}, 0x3);
  } else {
    using V2 = typename Lanes<2>::V;
    return __builtin_ia32_rsqrt14pd128_mask(V2{q, q}, V2{}, 0x3)[0];
  }
}
#endif

// 1/√q for C lanes of q in [2⁻¹⁰², 32) (a normalized squared length), to ~2e-14 relative or
// better. Rsqrt14 (AVX-512 hosts): vrsqrt14pd and two Newton steps in double (2⁻¹⁴ → 2⁻²⁸ →
// rounding), a short chain: the loop over faces waits on it, and this took the row divergence
// of a 1M-face block of 32 from 47 to 41 ms (docs/decisions.md, "Blocks of sources, session
// 14"). Otherwise a float square root and division (half-width lanes, short latency) and one
// Newton step in double, which squares float's relative error (~1e-7 → ~2e-14). The divider, not
// memory, bounded the row divergence with double sqrt and division. The same arithmetic for
// every C, so a column's bits do not depend on the chunk it falls in.
template <int C, bool Rsqrt14>
[[gnu::always_inline]] inline typename Lanes<C>::V inverse_sqrt(typename Lanes<C>::V q) {
  using V = typename Lanes<C>::V;
  const V half_q = 0.5 * q;
  V r0;
#if IFEM_RSQRT14
  if constexpr (Rsqrt14) {
    r0 = rsqrt14<C>(q);
    r0 = r0 * (1.5 - half_q * (r0 * r0));
    return r0 * (1.5 - half_q * (r0 * r0));
  }
#endif
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
template <int C, bool Rsqrt14>
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
  const V r = inverse_sqrt<C, Rsqrt14>(nx * nx + ny * ny);
  const V p0 = (y * half_s) * nx - ((x - l0) * half_s) * ny;
  const V p1 = (x * half_s) * ny - (y * half_s) * nx;
  const V p2 = (-l0 * half_s) * ny;
  lanes::store<C>(d[0], lanes::load<C>(d[0]) + where<C>(ok, p0 * r));
  lanes::store<C>(d[1], lanes::load<C>(d[1]) + where<C>(ok, p1 * r));
  lanes::store<C>(d[2], lanes::load<C>(d[2]) + where<C>(ok, p2 * r));
}

// unit_corners_lanes() on columns [j, j + C) of the rows u and d.
template <int C, bool Rsqrt14>
[[gnu::always_inline]] inline void unit_corners_at(const double* fr, const double* const u[3],
                                                   double* const d[3], Index j, double half_s) {
  const double* uj[3] = {u[0] + j, u[1] + j, u[2] + j};
  double* dj[3] = {d[0] + j, d[1] + j, d[2] + j};
  unit_corners_lanes<C, Rsqrt14>(fr, uj, dj, half_s);
}

// Columns [j0, j1) of apply_rows(): faces in order, chunks of 8, 4, 2, 1 columns.
template <bool Rsqrt14>
[[gnu::always_inline]] inline void divergence_rows(const double* frame, const Index* tail, Index nf,
                                                   const double* U, const Index* u_row,
                                                   const Index* d_row, Index k, Index j0, Index j1,
                                                   double half_s, double* div) {
  // the row of U that holds vertex v's values: v, or u_row[v]
  auto at = [U, u_row, k](Index v) { return U + (u_row ? u_row[v] : v) * k; };
  auto dt = [div, d_row, k](Index v) { return div + (d_row ? d_row[v] : v) * k; };
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
    for (; j + 8 <= j1; j += 8) unit_corners_at<8, Rsqrt14>(fr, u, d, j, half_s);
    if (j + 4 <= j1) unit_corners_at<4, Rsqrt14>(fr, u, d, j, half_s), j += 4;
    if (j + 2 <= j1) unit_corners_at<2, Rsqrt14>(fr, u, d, j, half_s), j += 2;
    if (j < j1) unit_corners_at<1, Rsqrt14>(fr, u, d, j, half_s);
  }
}

IFEM_HOST_CLONES void unit_divergence_rows_portable(const double* frame, const Index* tail,
                                                    Index nf, const double* U, const Index* u_row,
                                                    const Index* d_row, Index k, Index j0, Index j1,
                                                    double half_s, double* div) {
  divergence_rows<false>(frame, tail, nf, U, u_row, d_row, k, j0, j1, half_s, div);
}

#if IFEM_RSQRT14
__attribute__((target("arch=x86-64-v4"))) void unit_divergence_rows_avx512(
    const double* frame, const Index* tail, Index nf, const double* U, const Index* u_row,
    const Index* d_row, Index k, Index j0, Index j1, double half_s, double* div) {
  divergence_rows<true>(frame, tail, nf, U, u_row, d_row, k, j0, j1, half_s, div);
}
#endif

std::atomic<bool> avx512_allowed{true};

// divergence_rows() for the host: its AVX-512 variant where the host has AVX-512 F and VL (and
// allow_avx512() left it on), else the portable one (cloned for x86-64-v4, v3 and the baseline).
void unit_divergence_rows(const double* frame, const Index* tail, Index nf, const double* U,
                          const Index* u_row, const Index* d_row, Index k, Index j0, Index j1,
                          double half_s, double* div) {
#if IFEM_RSQRT14
  if (lanes::host_has_avx512() && avx512_allowed.load(std::memory_order_relaxed)) {
    unit_divergence_rows_avx512(frame, tail, nf, U, u_row, d_row, k, j0, j1, half_s, div);
    return;
  }
#endif
  unit_divergence_rows_portable(frame, tail, nf, U, u_row, d_row, k, j0, j1, half_s, div);
}

}  // namespace

void UnitGradientDivergence::apply_rows(const double* U, Eigen::Index k, double* div) const {
  if (k < 1) throw InvalidInput("divergence_of_unit_gradients: need at least one column");
  const Index nv = n_vertices_, nf = n_faces_;
  const double half_s = 0.5 * scale_;
  // Threads split the columns at a multiple of 8 (whole vectors and, for k = 32, whole cache
  // lines of a row); each zeroes and sums its own columns in face order.
  const bool two = k >= 16 && parallel_pays(nf, kParallelFaces);
#pragma omp parallel num_threads(2) if (two)
  {
#ifdef _OPENMP
    const Index nt = omp_get_num_threads(), t = omp_get_thread_num();
#else
    const Index nt = 1, t = 0;
#endif
    const Index mid = column_split(k);
    const Index j0 = t == 0 ? 0 : mid, j1 = t + 1 == nt ? k : mid;
    for (Index v = 0; v < nv; ++v) std::fill(div + v * k + j0, div + v * k + j1, 0.0);
    unit_divergence_rows(frame_.data(), tail_.data(), nf, U, nullptr, nullptr, k, j0, j1, half_s,
                         div);
  }
}

void UnitGradientDivergence::apply_rows(const double* U, Eigen::Index k, double* div,
                                        Eigen::Index j0, Eigen::Index j1, const Index* u_row,
                                        const Index* d_row) const {
  if (k < 1 || j0 < 0 || j0 > j1 || j1 > k) {
    throw InvalidInput("UnitGradientDivergence::apply_rows: columns [" + std::to_string(j0) + ", " +
                       std::to_string(j1) + ") not within [0, " + std::to_string(k) + ")");
  }
  const Index nv = n_vertices_;
  for (Index v = 0; v < nv; ++v) std::fill(div + v * k + j0, div + v * k + j1, 0.0);
  unit_divergence_rows(frame_.data(), tail_.data(), n_faces_, U, u_row, d_row, k, j0, j1,
                       0.5 * scale_, div);
}

void UnitGradientDivergence::add_rows_part(const double* U, Eigen::Index k, double* div, int part,
                                           Eigen::Index j0, Eigen::Index j1, const Index* u_row,
                                           const Index* d_row) const {
  if (k < 1 || j0 < 0 || j0 > j1 || j1 > k || part < 0 || part > 2) {
    throw InvalidInput("UnitGradientDivergence::add_rows_part: part " + std::to_string(part) +
                       ", columns [" + std::to_string(j0) + ", " + std::to_string(j1) +
                       ") (need part 0, 1 or 2 and columns within [0, " + std::to_string(k) + "))");
  }
  const Index f0 = part == 0 ? 0 : part == 1 ? part_faces_[0] : part_faces_[0] + part_faces_[1];
  const Index f1 = part == 0 ? part_faces_[0] : part == 1 ? f0 + part_faces_[1] : n_faces_;
  unit_divergence_rows(frame_.data() + 3 * f0, tail_.data() + 3 * f0, f1 - f0, U, u_row, d_row, k,
                       j0, j1, 0.5 * scale_, div);
}

UnitGradientDivergence UnitGradientDivergence::relabeled(
    const std::vector<Index>& new_index) const {
  const Index nv = n_vertices_;
  std::vector<char> seen(static_cast<std::size_t>(nv), 0);
  bool ok = Index(new_index.size()) == nv;
  for (std::size_t v = 0; ok && v < new_index.size(); ++v) {
    const Index w = new_index[v];
    ok = w >= 0 && w < nv && !seen[std::size_t(w)];
    if (ok) seen[std::size_t(w)] = 1;
  }
  if (!ok) {
    throw InvalidInput("UnitGradientDivergence::relabeled: new_index is not a permutation of [0, " +
                       std::to_string(nv) + ")");
  }
  // faces in three parts (every new corner below #V/2, every one at or above, both), each by
  // its smallest new corner, so that a pass over a part sweeps the new order
  const Index nf = n_faces_, half = nv / 2;
  std::vector<Index> lowest(static_cast<std::size_t>(nf)), face(static_cast<std::size_t>(nf));
  std::vector<int> part(static_cast<std::size_t>(nf));
  for (Index f = 0; f < nf; ++f) {
    const Index* t = tail_.data() + 3 * f;
    const Index a = new_index[std::size_t(t[0])], b = new_index[std::size_t(t[1])],
                c = new_index[std::size_t(t[2])];
    lowest[std::size_t(f)] = std::min({a, b, c});
    const Index highest = std::max({a, b, c});
    part[std::size_t(f)] = highest < half ? 0 : lowest[std::size_t(f)] >= half ? 1 : 2;
  }
  std::iota(face.begin(), face.end(), Index(0));
  std::stable_sort(face.begin(), face.end(), [&](Index a, Index b) {
    const std::size_t i = std::size_t(a), j = std::size_t(b);
    return part[i] != part[j] ? part[i] < part[j] : lowest[i] < lowest[j];
  });
  UnitGradientDivergence copy = *this;
  copy.part_faces_ = {0, 0};
  for (const int q : part) {
    if (q < 2) ++copy.part_faces_[std::size_t(q)];
  }
  for (Index i = 0; i < nf; ++i) {
    const std::size_t f = std::size_t(face[std::size_t(i)]);
    for (int c = 0; c < 3; ++c) {
      copy.tail_[3 * std::size_t(i) + c] = new_index[std::size_t(tail_[3 * f + c])];
      copy.frame_[3 * std::size_t(i) + c] = frame_[3 * f + c];
    }
  }
  return copy;
}

bool UnitGradientDivergence::allow_avx512(bool allowed) { return avx512_allowed.exchange(allowed); }

Eigen::Index UnitGradientDivergence::column_split(Eigen::Index k) {
  return k < 16 ? k : (k / 2 + 7) / 8 * 8;
}

}  // namespace ifem::fem
