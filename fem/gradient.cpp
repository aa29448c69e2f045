#include "fem/gradient.h"

#include <algorithm>
#include <cmath>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"

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

// The corner contributions s·A·∇φ_i·X of face f (with hat gradients g) to the divergence of the
// unit field −∇u/|∇u|, u at the face's corners; false where the field is undefined.
bool unit_divergence_corners(const Layout& L, const Eigen::Vector2d g[3], double u0, double u1,
                             double u2, double s, double c[3]) {
  Eigen::Vector2d x = u0 * g[0] + u1 * g[1] + u2 * g[2];
  if (!negate_normalize(x)) return false;
  for (int i = 0; i < 3; ++i) c[i] = s * L.area * g[i].dot(x);
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
  if (u.size() != tri.n_vertices()) {
    throw InvalidInput("divergence_of_unit_gradient: u has " + std::to_string(u.size()) +
                       " values, expected #V = " + std::to_string(tri.n_vertices()));
  }
  const Index nf = tri.n_faces();
  if (use_face && static_cast<Index>(use_face->size()) != nf) {
    throw InvalidInput("divergence_of_unit_gradient: use_face has " +
                       std::to_string(use_face->size()) +
                       " entries, expected #F = " + std::to_string(nf));
  }
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> c(nf, 3);
  const double s = 1.0 / tri.multiplicity();
  const auto& tail = tri.tails();
#pragma omp parallel for schedule(static) if (nf >= kParallelFaces)
  for (Index f = 0; f < nf; ++f) {
    c.row(f).setZero();
    if (use_face && !(*use_face)[f]) continue;
    const Layout L = layout(tri, f);
    Eigen::Vector2d g[3];
    if (!hat_gradients(L, g)) continue;
    double cf[3];
    if (!unit_divergence_corners(L, g, u[tail[3 * f]], u[tail[3 * f + 1]], u[tail[3 * f + 2]], s,
                                 cf)) {
      continue;
    }
    for (int i = 0; i < 3; ++i) c(f, i) = cf[i];
  }
  Eigen::VectorXd div = Eigen::VectorXd::Zero(tri.n_vertices());
  for (Index f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) div[tail[3 * f + i]] += c(f, i);
  }
  return div;
}

Eigen::MatrixXd divergence_of_unit_gradients(const IntrinsicTriangulation& tri,
                                             const Eigen::MatrixXd& U,
                                             const std::vector<std::vector<char>>& use_face) {
  const Index nv = tri.n_vertices(), nf = tri.n_faces();
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
  // vertex-major copies: a face's k values per corner are contiguous
  const Eigen::MatrixXd Ut = U.transpose();
  Eigen::MatrixXd div = Eigen::MatrixXd::Zero(k, nv);
  const double s = 1.0 / tri.multiplicity();
  const auto& tail = tri.tails();
  // columns split between threads: each scatters into its own columns, no atomics
#pragma omp parallel if (nf >= kParallelFaces && k > 1)
  {
#ifdef _OPENMP
    const Eigen::Index nt = omp_get_num_threads(), t = omp_get_thread_num();
#else
    const Eigen::Index nt = 1, t = 0;
#endif
    const Eigen::Index j0 = k * t / nt, j1 = k * (t + 1) / nt;
    for (Index f = 0; f < nf && j0 < j1; ++f) {
      const Layout L = layout(tri, f);
      Eigen::Vector2d g[3];
      if (!hat_gradients(L, g)) continue;
      const Index a = tail[3 * f], b = tail[3 * f + 1], c = tail[3 * f + 2];
      for (Eigen::Index j = j0; j < j1; ++j) {
        if (!use_face.empty() && !use_face[std::size_t(j)][std::size_t(f)]) continue;
        double cf[3];
        if (!unit_divergence_corners(L, g, Ut(j, a), Ut(j, b), Ut(j, c), s, cf)) continue;
        div(j, a) += cf[0];
        div(j, b) += cf[1];
        div(j, c) += cf[2];
      }
    }
  }
  return div.transpose();
}

}  // namespace ifem::fem
