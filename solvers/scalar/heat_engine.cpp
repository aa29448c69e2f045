#include "solvers/scalar/heat_engine.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "fem/gradient.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "solvers/linalg/row_kernels.h"

namespace ifem::solvers {

namespace {

// OpenMP regions below this many faces run serially: waking a thread costs more than the whole
// loop on a small mesh.
constexpr Index kParallelFaces = 20000;

// Two OpenMP threads, or one when OpenMP's thread count (omp_set_num_threads) is 1.
int at_most_two_threads() {
#ifdef _OPENMP
  return omp_get_max_threads() > 1 ? 2 : 1;
#else
  return 1;
#endif
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

Eigen::VectorXd divergence_of_unit_gradient(const intrinsic::IntrinsicTriangulation& tri,
                                            const Eigen::VectorXd& u,
                                            const std::vector<char>* use_face) {
  return UnitGradientDivergence(tri).apply(u, use_face);
}

Eigen::MatrixXd divergence_of_unit_gradients(const intrinsic::IntrinsicTriangulation& tri,
                                             const Eigen::MatrixXd& U,
                                             const std::vector<std::vector<char>>& use_face) {
  return UnitGradientDivergence(tri).apply_columns(U, use_face);
}

UnitGradientDivergence::UnitGradientDivergence(const intrinsic::IntrinsicTriangulation& tri)
    : n_vertices_(tri.n_vertices()),
      n_faces_(tri.n_faces()),
      scale_(1.0 / tri.multiplicity()),
      tail_(tri.tails().begin(), tri.tails().end()),
      frame_(3 * std::size_t(tri.n_faces())) {
  const Index nf = n_faces_;
#pragma omp parallel for schedule(static) if (nf >= kParallelFaces)
  for (Index f = 0; f < nf; ++f) {
    const double l0 = tri.halfedge_length(3 * f);
    const double area = intrinsic::triangle_area(l0, tri.halfedge_length(3 * f + 1),
                                                 tri.halfedge_length(3 * f + 2));
    const Eigen::Vector2d apex = fem::face_corner2(tri, f);
    double* fr = &frame_[3 * std::size_t(f)];
    fr[0] = l0;
    fr[1] = apex.x();
    fr[2] = area > 0.0 && apex.y() > 0.0 ? apex.y() : 0.0;
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
  const bool two = nf >= kParallelFaces;
  if (nf >= kParallelFaces) half[1] = Eigen::VectorXd::Zero(n_vertices_);
  const int parts = nf >= kParallelFaces ? 2 : 1;
  const Index mid = face_split();  // (add_faces()'s callers split at the same face)
#pragma omp parallel for schedule(static, 1) num_threads(at_most_two_threads()) if (two)
  for (int part = 0; part < parts; ++part) {
    double* div = half[part].data();
    const Index f1 = part == 0 ? 0 : mid, f2 = part == 0 ? mid : nf;
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

void UnitGradientDivergence::add_faces(const Index* faces, Index n, const double* u,
                                       const Index* local, double* div) const {
  const double half_s = 0.5 * scale_;
  for (Index i = 0; i < n; ++i) {
    const Index* t = &tail_[3 * std::size_t(faces[i])];
    const Index a = local[t[0]], b = local[t[1]], c3 = local[t[2]];
    double c[3];
    if (!unit_corners(&frame_[3 * std::size_t(faces[i])], u[a], u[b], u[c3], half_s, c)) continue;
    div[a] += c[0];
    div[b] += c[1];
    div[c3] += c[2];
  }
}

Index UnitGradientDivergence::face_split() const {
  return n_faces_ >= kParallelFaces ? n_faces_ / 2 : n_faces_;
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
#pragma omp parallel if (k > 1 && nf >= kParallelFaces)
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

void UnitGradientDivergence::apply_rows(const double* U, Eigen::Index k, double* div) const {
  if (k < 1) throw InvalidInput("divergence_of_unit_gradients: need at least one column");
  const Index nv = n_vertices_, nf = n_faces_;
  const double half_s = 0.5 * scale_;
  // Threads split the columns at a multiple of 8 (whole vectors and, for k = 32, whole cache
  // lines of a row); each zeroes and sums its own columns in face order.
  const bool two = k >= 16 && nf >= kParallelFaces;
#pragma omp parallel num_threads(at_most_two_threads()) if (two)
  {
#ifdef _OPENMP
    const Index nt = omp_get_num_threads(), t = omp_get_thread_num();
#else
    const Index nt = 1, t = 0;
#endif
    const Index mid = column_split(k);
    const Index j0 = t == 0 ? 0 : mid, j1 = t + 1 == nt ? k : mid;
    for (Index v = 0; v < nv; ++v) std::fill(div + v * k + j0, div + v * k + j1, 0.0);
    unit_divergence_rows(frame_.data(), tail_.data(), nf, U, nullptr, nullptr, Index(k), Index(j0),
                         Index(j1), half_s, div);
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
  unit_divergence_rows(frame_.data(), tail_.data(), n_faces_, U, u_row, d_row, Index(k), Index(j0),
                       Index(j1), 0.5 * scale_, div);
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
  unit_divergence_rows(frame_.data() + 3 * f0, tail_.data() + 3 * f0, f1 - f0, U, u_row, d_row,
                       Index(k), Index(j0), Index(j1), 0.5 * scale_, div);
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

Eigen::Index UnitGradientDivergence::column_split(Eigen::Index k) {
  return k < 16 ? k : (k / 2 + 7) / 8 * 8;
}

}  // namespace ifem::solvers
