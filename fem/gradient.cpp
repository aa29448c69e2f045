#include "fem/gradient.h"

#include <string>

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

}  // namespace ifem::fem
