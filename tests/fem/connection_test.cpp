// Tangent frames and the connection Laplacian (fem/connection.h): transport, holonomy, and the
// operator's spectrum against what the geometry dictates (flat cylinder and torus: the scalar
// Laplacian's; sphere: no parallel field).
#include "fem/connection.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <queue>
#include <utility>
#include <vector>

#include "fem/operators.h"
#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/surface/tufted_cover.h"
#include "support/dense_spectrum.h"

namespace ifem::fem {
namespace {

using intrinsic::IntrinsicTriangulation;
using intrinsic::kPi;
using intrinsic::TriangleMesh;
using T = IntrinsicTriangulation;
using Complex = std::complex<double>;

// x reduced to (−π, π].
double wrapped(double x) { return std::remainder(x, 2 * kPi); }

IntrinsicTriangulation from_mesh(const TriangleMesh& m) {
  return IntrinsicTriangulation::from_positions(m.faces, m.positions);
}

// A jittered unit square with a Gaussian bump: curved inside, boundary corners and sides.
TriangleMesh bumpy_grid(int n) {
  TriangleMesh m = test::jittered(intrinsic::grid(n, n), 0.3 / n);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const double x = m.positions(v, 0) - 0.5, y = m.positions(v, 1) - 0.5;
    m.positions(v, 2) = 0.4 * std::exp(-(x * x + y * y) / 0.05);
  }
  return m;
}

// A flat cylinder (periodic in i) or torus (periodic in i and j): the lattice (i, j) ↦
// (i + 0.35 j, 0.8 j) with a periodic jitter, glued by side lengths. On the cylinder the two
// boundary rows are jittered along themselves only, so they stay straight (angle sum π).
IntrinsicTriangulation flat_periodic(int nx, int ny, bool torus) {
  const int rows = torus ? ny : ny + 1;
  auto id = [&](int i, int j) { return Index((i % nx) + nx * (j % rows)); };
  auto jitter = [&](int i, int j, int k) {
    const unsigned s = 2654435761u * unsigned(id(i, j) * 2 + k + 1);
    return 0.25 * ((s >> 8) / double(1u << 24) - 0.5);
  };
  auto pos = [&](int i, int j) {
    const bool edge_row = !torus && (j == 0 || j == ny);
    return Eigen::Vector2d(i + 0.35 * j + jitter(i, j, 0),
                           0.8 * j + (edge_row ? 0.0 : jitter(i, j, 1)));
  };
  std::vector<Triangle> faces;
  std::vector<std::array<Eigen::Vector2d, 3>> corners;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int c[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
      for (const auto& t : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}}) {
        faces.push_back(
            {id(c[t[0]][0], c[t[0]][1]), id(c[t[1]][0], c[t[1]][1]), id(c[t[2]][0], c[t[2]][1])});
        corners.push_back({pos(c[t[0]][0], c[t[0]][1]), pos(c[t[1]][0], c[t[1]][1]),
                           pos(c[t[2]][0], c[t[2]][1])});
      }
    }
  }
  Eigen::MatrixX3d l(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int s = 0; s < 3; ++s) l(f, s) = (corners[f][(s + 1) % 3] - corners[f][s]).norm();
  }
  auto tri = IntrinsicTriangulation::from_side_lengths(faces, nx * rows, l);
  tri.flip_to_delaunay();
  return tri;
}

// Interior vertices: every outgoing halfedge has a twin.
std::vector<char> boundary_vertices(const IntrinsicTriangulation& tri) {
  std::vector<char> b(tri.n_vertices(), 0);
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    if (tri.twin(h) == kInvalidIndex) b[tri.tail(h)] = b[tri.head(h)] = 1;
  }
  return b;
}

// What the frames promise on any triangulation with one fan per vertex.
void expect_frame_properties(const IntrinsicTriangulation& tri, const TangentFrames& fr) {
  ASSERT_EQ(fr.transport.size(), tri.n_halfedges());
  const Eigen::VectorXd theta = intrinsic::vertex_angle_sums(tri);
  const std::vector<char> boundary = boundary_vertices(tri);
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    EXPECT_NEAR(fr.angle_sum[v], theta[v], 1e-12 * theta[v]);
    // interior fans fill one turn; boundary fans keep their true angles up to one turn
    EXPECT_NEAR(fr.angle_scale[v] * theta[v], boundary[v] ? std::min(theta[v], 2 * kPi) : 2 * kPi,
                1e-12)
        << v;
    EXPECT_EQ(fr.halfedge_angle[tri.vertex_halfedge(v)], 0.0) << v;
  }
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    EXPECT_GE(fr.halfedge_angle[h], 0.0);
    EXPECT_LT(fr.halfedge_angle[h], 2 * kPi);
    EXPECT_NEAR(std::abs(fr.transport[h]), 1.0, 1e-14);
    // counter-clockwise: the next outgoing halfedge is one scaled corner further
    const Index v = tri.tail(h), n = tri.twin(T::prev(h));
    const double step = fr.angle_scale[v] * intrinsic::corner_angle(tri, h);
    if (n != kInvalidIndex) {
      EXPECT_NEAR(wrapped(fr.halfedge_angle[n] - fr.halfedge_angle[h] - step), 0.0, 1e-12) << h;
    } else {  // the fan's last side is the incoming boundary edge, at scale × Θ
      EXPECT_NEAR(wrapped(fr.halfedge_angle[h] + step - fr.angle_scale[v] * theta[v]), 0.0, 1e-12)
          << h;
    }
    if (tri.twin(h) != kInvalidIndex) {  // there and back again: unchanged
      EXPECT_LT(std::abs(fr.transport[h] * fr.transport[tri.twin(h)] - 1.0), 1e-14) << h;
    }
  }
}

// Triangulations of curved surfaces with one fan per vertex: the icosphere, a jittered bumpy
// square, and the latter refined to intrinsic Delaunay (flips, insertions, boundary splits).
std::vector<IntrinsicTriangulation> curved_cases() {
  std::vector<IntrinsicTriangulation> out;
  out.push_back(from_mesh(intrinsic::icosphere(6)));
  out.push_back(from_mesh(bumpy_grid(12)));
  IntrinsicTriangulation refined = from_mesh(bumpy_grid(12));
  intrinsic::RefineOptions opt;
  opt.min_angle_degrees = 28.0;
  opt.max_area = intrinsic::equilateral_area(0.5 / 12);  // splits boundary edges too
  const auto report = intrinsic::delaunay_refine(refined, opt);
  EXPECT_GT(report.insertions, 0);
  EXPECT_GT(report.boundary_splits, 0);
  EXPECT_GT(report.flips, 0u);
  out.push_back(std::move(refined));
  return out;
}

TEST(Connection, TransportIsUnitAndInvertible) {
  for (const auto& tri : curved_cases()) {
    SCOPED_TRACE(tri.n_vertices());
    expect_frame_properties(tri, tangent_frames(tri));
  }
}

TEST(Connection, HolonomyEqualsAngleDefect) {
  for (const auto& tri : curved_cases()) {
    SCOPED_TRACE(tri.n_vertices());
    const TangentFrames fr = tangent_frames(tri);
    const Eigen::VectorXd defect = intrinsic::angle_defects(tri);  // π − Θ on the boundary
    const std::vector<char> boundary = boundary_vertices(tri);
    double largest = 0.0;
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      // a boundary vertex (Θ ≤ 2π here) keeps its true angles: no holonomy; the boundary's
      // turning π − Θ is not the connection's
      const double expected = boundary[v] ? 0.0 : defect[v];
      EXPECT_LT(fr.angle_sum[v], boundary[v] ? 2 * kPi : 1e9) << v;
      EXPECT_NEAR(wrapped(fr.holonomy_around(tri, v) - expected), 0.0, 1e-10) << v;
      if (!boundary[v]) largest = std::max(largest, std::abs(defect[v]));
    }
    EXPECT_GT(largest, 1e-3);  // curved: the test compares non-trivial angles
  }
}

Eigen::MatrixXcd dense(const ComplexSparseMatrix& L) { return Eigen::MatrixXcd(L); }

// Eigenvalues of the pencil (L, diag(mass)), ascending, over vertices with mass.
template <class Matrix>
Eigen::VectorXd generalized_eigenvalues(const Matrix& L, const Eigen::VectorXd& mass) {
  std::vector<Index> keep;
  for (Index v = 0; v < mass.size(); ++v) {
    if (mass[v] > 0.0) keep.push_back(v);
  }
  Matrix A(keep.size(), keep.size());
  for (std::size_t a = 0; a < keep.size(); ++a) {
    for (std::size_t b = 0; b < keep.size(); ++b) {
      A(a, b) = L(keep[a], keep[b]) / std::sqrt(mass[keep[a]] * mass[keep[b]]);
    }
  }
  return test::self_adjoint_eigenvalues(A);
}

// Hermitian to 1e-14 relative, real non-negative diagonal, finite, PSD to 1e-10 relative.
void expect_hermitian_psd(const ComplexSparseMatrix& L) {
  const Eigen::MatrixXcd D = dense(L);
  ASSERT_TRUE(D.allFinite());
  const double scale = D.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LE((D - D.adjoint()).cwiseAbs().maxCoeff(), 1e-14 * scale);
  for (Eigen::Index v = 0; v < D.rows(); ++v) {
    EXPECT_EQ(D(v, v).imag(), 0.0);
    EXPECT_GE(D(v, v).real(), 0.0);
  }
  const Eigen::VectorXd ev = test::self_adjoint_eigenvalues(D);
  EXPECT_GE(ev.minCoeff(), -1e-10 * ev.maxCoeff());
}

TEST(Connection, LaplacianIsHermitianPsdForEverySymmetry) {
  IntrinsicTriangulation bumpy = from_mesh(bumpy_grid(10));
  bumpy.flip_to_delaunay();
  const IntrinsicTriangulation sphere = from_mesh(intrinsic::icosphere(3));
  for (const IntrinsicTriangulation* tri : {&std::as_const(bumpy), &sphere}) {
    const TangentFrames fr = tangent_frames(*tri);
    for (const int n : {1, 2, 4}) {
      SCOPED_TRACE(n);
      const ComplexSparseMatrix L = connection_laplacian(*tri, fr, n);
      expect_hermitian_psd(L);
      // the diagonal is the scalar Laplacian's (no self-edges here)
      const SparseMatrix S = cotan_laplacian(*tri);
      EXPECT_LE((L.diagonal().real() - S.diagonal()).cwiseAbs().maxCoeff(),
                1e-14 * S.diagonal().maxCoeff());
    }
  }
  const TangentFrames fr = tangent_frames(sphere);
  EXPECT_THROW(connection_laplacian(sphere, fr, 0), InvalidInput);
  EXPECT_THROW(connection_laplacian(bumpy, fr, 1), InvalidInput);  // another triangulation's
}

// A parallel field: x_0 = 1 carried along a breadth-first spanning tree (x_j = r_{i→j} x_i).
Eigen::VectorXcd transported_from_root(const IntrinsicTriangulation& tri, const TangentFrames& fr) {
  std::vector<std::vector<std::pair<Index, Complex>>> adj(tri.n_vertices());
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    adj[tri.tail(h)].push_back({tri.head(h), fr.transport[h]});
    adj[tri.head(h)].push_back({tri.tail(h), std::conj(fr.transport[h])});
  }
  Eigen::VectorXcd x = Eigen::VectorXcd::Zero(tri.n_vertices());
  std::queue<Index> queue;
  x[0] = 1.0;
  queue.push(0);
  while (!queue.empty()) {
    const Index i = queue.front();
    queue.pop();
    for (const auto& [j, r] : adj[i]) {
      if (x[j] != Complex(0.0)) continue;
      x[j] = r * x[i];
      queue.push(j);
    }
  }
  return x;
}

// On a flat cylinder or torus the connection is trivial: the transported field is
// path-independent, lies in the kernel, and gauges L into the scalar Laplacian, so their
// spectra (with the lumped mass) agree.
void expect_flat_connection(const IntrinsicTriangulation& tri) {
  const TangentFrames fr = tangent_frames(tri);
  const Eigen::VectorXd defect = intrinsic::angle_defects(tri);
  EXPECT_LT(defect.cwiseAbs().maxCoeff(), 1e-12);  // flat, straight boundary
  const Eigen::VectorXcd x = transported_from_root(tri, fr);
  for (Index e = 0; e < tri.n_edges(); ++e) {  // path independence: every edge agrees
    const Index h = tri.edge_halfedge(e);
    ASSERT_LT(std::abs(x[tri.head(h)] - fr.transport[h] * x[tri.tail(h)]), 1e-12) << e;
  }
  const SparseMatrix S = cotan_laplacian(tri);
  const Eigen::VectorXd mass = lumped_mass(tri);
  const Eigen::VectorXd scalar = generalized_eigenvalues(Eigen::MatrixXd(S), mass);
  for (const int n : {1, 2, 4}) {
    SCOPED_TRACE(n);
    const ComplexSparseMatrix L = connection_laplacian(tri, fr, n);
    const Eigen::VectorXcd xn = x.array().pow(n);
    const double scale = S.diagonal().maxCoeff();
    EXPECT_LT((L * xn).cwiseAbs().maxCoeff(), 1e-12 * scale);  // the parallel field
    const Eigen::MatrixXcd gauged = xn.conjugate().asDiagonal() * dense(L) * xn.asDiagonal();
    EXPECT_LT((gauged - Eigen::MatrixXcd(S.cast<Complex>())).cwiseAbs().maxCoeff(), 1e-12 * scale);
    const Eigen::VectorXd complex = generalized_eigenvalues(dense(L), mass);
    EXPECT_LT(std::abs(complex[0]), 1e-9 * scalar.maxCoeff());
    EXPECT_LT((complex - scalar).cwiseAbs().maxCoeff(), 1e-9 * scalar.maxCoeff());
  }
}

TEST(Connection, FlatCylinderHasTheScalarSpectrum) {
  expect_flat_connection(flat_periodic(12, 8, false));
}

TEST(Connection, FlatTorusHasAParallelField) {
  const IntrinsicTriangulation torus = flat_periodic(12, 9, true);
  ASSERT_FALSE(torus.has_boundary());
  ASSERT_EQ(intrinsic::euler_characteristic(torus), 0);
  expect_flat_connection(torus);
  // and only one (up to a complex factor): the second eigenvalue is well away from zero
  const Eigen::VectorXd ev = generalized_eigenvalues(
      dense(connection_laplacian(torus, tangent_frames(torus))), lumped_mass(torus));
  EXPECT_GT(ev[1], 1e-3 * ev.maxCoeff());
}

TEST(Connection, SphereSpectrumIsAnalytic) {
  // On the unit sphere the connection Laplacian of n-direction fields (sections of the n-th
  // power of the tangent bundle, spin weight n) has eigenvalues l(l + 1) − n², l ≥ n, each
  // 2l + 1 times: the smallest is n (for n = 1: 2 − 1, Weitzenböck's Δ_Hodge − Ric on the
  // gradients of the l = 1 harmonics), never 0 — a sphere has no parallel field.
  const IntrinsicTriangulation sphere = from_mesh(intrinsic::icosphere(8));
  const TangentFrames fr = tangent_frames(sphere);
  const Eigen::VectorXd mass = lumped_mass(sphere);
  for (const int n : {1, 2, 4}) {
    SCOPED_TRACE(n);
    const Eigen::VectorXd ev =
        generalized_eigenvalues(dense(connection_laplacian(sphere, fr, n)), mass);
    int k = 0;
    for (int l = n; l <= n + 1; ++l) {
      const double expected = l * (l + 1) - n * n;
      for (int copy = 0; copy < 2 * l + 1; ++copy, ++k) {
        EXPECT_NEAR(ev[k], expected, 0.03 * expected) << "l " << l;
      }
    }
  }
}

TEST(Connection, IntrinsicDelaunayWeightsAreNonNegative) {
  const TriangleMesh m = test::jittered(intrinsic::uv_sphere(8, 120), 0.02);
  IntrinsicTriangulation tri = from_mesh(m);
  // the input's needle fans have negative weights (positive scalar off-diagonals)
  EXPECT_GT(cotan_laplacian(tri).coeffs().maxCoeff(), 0.0);
  tri.flip_to_delaunay();
  const TangentFrames fr = tangent_frames(tri);
  const ComplexSparseMatrix L = connection_laplacian(tri, fr);
  const SparseMatrix S = cotan_laplacian(tri);
  const double scale = S.diagonal().maxCoeff();
  for (int k = 0; k < L.outerSize(); ++k) {
    for (ComplexSparseMatrix::InnerIterator it(L, k); it; ++it) {
      const double s = S.coeff(it.row(), it.col());
      if (it.row() == it.col()) {
        EXPECT_NEAR(it.value().real(), s, 1e-14 * scale);
      } else {
        ASSERT_LE(s, 1e-12 * scale);                          // w_ij ≥ 0
        EXPECT_LE(std::abs(it.value()), -s + 1e-14 * scale);  // |Σ w r| ≤ Σ w
      }
    }
  }
}

TEST(Connection, NonDelaunayInputCanBeIndefinite) {
  // Unlike the scalar cotan Laplacian, L is a sum of squares only with w ≥ 0: a negative weight
  // on an edge of a face with holonomy makes it indefinite. The skewed quad alone is flat with
  // a straight-sided boundary, so its connection is trivial (L is the scalar Laplacian turned);
  // doubled into a pillow (the back split along the other diagonal) its corners become cones
  // whose holonomy sits in the faces of the negative edge 0–2. The intrinsic Delaunay
  // triangulation of the same pillow is PSD.
  intrinsic::TriangleMesh pillow = test::skewed_quad();
  pillow.faces.push_back({1, 0, 3});
  pillow.faces.push_back({1, 3, 2});
  IntrinsicTriangulation tri = from_mesh(pillow);
  ASSERT_FALSE(tri.has_boundary());
  ASSERT_LT(intrinsic::cotan_weights(tri).minCoeff(), 0.0);
  auto smallest = [&](int n) {
    const Eigen::MatrixXcd L = dense(connection_laplacian(tri, tangent_frames(tri), n));
    const Eigen::VectorXd ev = test::self_adjoint_eigenvalues(L);
    return ev[0] / ev.maxCoeff();
  };
  EXPECT_LT(smallest(1), -1e-3);
  EXPECT_GE(cotan_laplacian(tri).diagonal().minCoeff(), 0.0);
  tri.flip_to_delaunay();
  for (const int n : {1, 2, 4}) EXPECT_GE(smallest(n), -1e-10) << n;
}

// A flat torus (unit square, periodic) from an n×n grid of squares split along a diagonal, with
// vertex (1, 1) pulled 95% of the way onto the diagonal of its square: a sliver whose angle near
// π puts a strongly negative cotan weight on that diagonal (and obtuse angles around it).
// Lengths from the plane, so every vertex is flat and the connection has no holonomy.
IntrinsicTriangulation flat_torus_with_sliver(int n) {
  auto id = [n](int i, int j) { return Index((j % n) * n + i % n); };
  auto position = [n](int i, int j) {
    Eigen::Vector2d p(double(i) / n, double(j) / n);
    if (i % n == 1 && j % n == 1) {  // towards the midpoint of (0, 1)–(1, 2)
      const Eigen::Vector2d mid = Eigen::Vector2d(i - 0.5, j + 0.5) / n;
      p += 0.95 * (mid - p);
    }
    return p;
  };
  std::vector<Triangle> faces;
  Eigen::MatrixX3d lengths(2 * n * n, 3);
  Index f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int corners[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}},
                                    {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
      for (const auto& c : corners) {
        faces.push_back({id(c[0][0], c[0][1]), id(c[1][0], c[1][1]), id(c[2][0], c[2][1])});
        for (int k = 0; k < 3; ++k) {
          const auto& a = c[k];
          const auto& b = c[(k + 1) % 3];
          // the sliver vertex also sits at (n + 1, ·) and (·, n + 1) seen across the seams
          lengths(f, k) = (position(b[0], b[1]) - position(a[0], a[1])).norm();
        }
        ++f;
      }
    }
  }
  return IntrinsicTriangulation::from_side_lengths(faces, n * n, lengths);
}

// The parallel field through p_0 = 1 (transport has no holonomy here: a breadth-first walk).
Eigen::VectorXcd parallel_field(const IntrinsicTriangulation& tri, const TangentFrames& fr) {
  Eigen::VectorXcd p = Eigen::VectorXcd::Zero(tri.n_vertices());
  p[0] = 1.0;
  std::queue<Index> todo;
  todo.push(0);
  while (!todo.empty()) {
    const Index v = todo.front();
    todo.pop();
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      if (tri.tail(h) != v || p[tri.head(h)] != Complex(0.0)) continue;
      p[tri.head(h)] = fr.transport[h] * p[v];
      todo.push(tri.head(h));
    }
  }
  return p;
}

// One implicit heat step (M + tL) x = M x0 of a field that is the constant direction at one
// vertex and 0 elsewhere, read against that direction at every vertex: min_v Re(conj(p_v) x_v)
// relative to the largest |x|, and where it is reached.
std::pair<double, Index> smoothed_against_constant(const IntrinsicTriangulation& tri, Index at,
                                                   double t) {
  const TangentFrames fr = tangent_frames(tri);
  const Eigen::VectorXcd p = parallel_field(tri, fr);
  for (Index h = 0; h < tri.n_halfedges(); ++h) {  // really parallel: no holonomy
    EXPECT_LT(std::abs(p[tri.head(h)] - fr.transport[h] * p[tri.tail(h)]), 1e-12);
  }
  const Eigen::VectorXd mass = lumped_mass(tri);
  ComplexSparseMatrix A = t * connection_laplacian(tri, fr, 1);
  for (Index v = 0; v < tri.n_vertices(); ++v) A.coeffRef(v, v) += mass[v];
  Eigen::SparseLU<ComplexSparseMatrix> lu(A);
  Eigen::VectorXcd b = Eigen::VectorXcd::Zero(tri.n_vertices());
  b[at] = mass[at] * p[at];
  const Eigen::VectorXcd x = lu.solve(b);
  std::pair<double, Index> worst{1e300, kInvalidIndex};
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    const double along = (std::conj(p[v]) * x[v]).real() / x.cwiseAbs().maxCoeff();
    if (along < worst.first) worst = {along, v};
  }
  return worst;
}

// The maximum principle the thesis cites (Fig. 4 right): on the intrinsic Delaunay
// triangulation the connection Laplacian's weights are non-negative, so a smoothing step keeps
// every vector within the half-plane of the constant direction it started from; the input's
// sliver gives a negative weight, and the vector across it comes out flipped.
TEST(Connection, IntrinsicDelaunaySmoothingFlipsNoVector) {
  const int n = 8;
  IntrinsicTriangulation tri = flat_torus_with_sliver(n);
  const Eigen::VectorXd w = intrinsic::cotan_weights(tri);
  Index worst_edge = 0;
  for (Index e = 0; e < tri.n_edges(); ++e) worst_edge = w[e] < w[worst_edge] ? e : worst_edge;
  ASSERT_LT(w[worst_edge], -1.0);  // the sliver's diagonal
  RecordProperty("sliver_weight", std::to_string(w[worst_edge]));
  const Index a = tri.tail(tri.edge_halfedge(worst_edge));
  const double t = 0.1 / (n * n);  // a tenth of h²
  const auto [input_min, input_at] = smoothed_against_constant(tri, a, t);
  EXPECT_LT(input_min, -1e-3) << "the input's Laplacian flips no vector here";
  EXPECT_EQ(input_at, tri.head(tri.edge_halfedge(worst_edge)));  // across the sliver's diagonal
  RecordProperty("input_min", std::to_string(input_min));
  tri.flip_to_delaunay();
  EXPECT_GE(intrinsic::cotan_weights(tri).minCoeff(), -1e-12);
  const auto [idt_min, idt_at] = smoothed_against_constant(tri, a, t);
  EXPECT_GE(idt_min, -1e-12) << "a flipped vector at vertex " << idt_at;
  RecordProperty("idt_min", std::to_string(idt_min));
}

// L from triplets, the documented formula edge by edge.
ComplexSparseMatrix reference_laplacian(const IntrinsicTriangulation& tri, const TangentFrames& fr,
                                        int n) {
  const Eigen::VectorXd w = intrinsic::cotan_weights(tri) / tri.multiplicity();
  std::vector<Eigen::Triplet<Complex>> t;
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tri.tail(h), j = tri.head(h);
    const Complex q = std::polar(1.0, n * std::arg(fr.transport[h]));  // r_{i→j}^n
    if (i == j) {
      t.emplace_back(i, i, w[e] * std::norm(1.0 - q));
      continue;
    }
    t.emplace_back(j, i, -w[e] * q);
    t.emplace_back(i, j, -w[e] * std::conj(q));
    t.emplace_back(i, i, w[e]);
    t.emplace_back(j, j, w[e]);
  }
  ComplexSparseMatrix L(tri.n_vertices(), tri.n_vertices());
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

void expect_matches_reference(const IntrinsicTriangulation& tri, const TangentFrames& fr) {
  for (const int n : {1, 2, 4}) {
    SCOPED_TRACE(n);
    const ComplexSparseMatrix L = connection_laplacian(tri, fr, n);
    expect_hermitian_psd(L);
    const Eigen::MatrixXcd diff = dense(L) - dense(reference_laplacian(tri, fr, n));
    EXPECT_LT(diff.cwiseAbs().maxCoeff(), 1e-13 * L.diagonal().cwiseAbs().maxCoeff());
  }
}

// An open fan of k flat isosceles triangles (spokes 1, apex angle theta / k) about vertex 0:
// a boundary vertex of angle sum theta, any theta (beyond 2π the fan overlaps itself, which
// intrinsic lengths allow). Rim vertices 1..k+1.
IntrinsicTriangulation boundary_fan(double theta, int k) {
  std::vector<Triangle> faces;
  Eigen::MatrixX3d l(k, 3);
  for (int i = 0; i < k; ++i) {
    faces.push_back({0, Index(i + 1), Index(i + 2)});
    l.row(i) << 1.0, 2.0 * std::sin(theta / (2 * k)), 1.0;
  }
  return IntrinsicTriangulation::from_side_lengths(faces, k + 2, l);
}

// Boundary vertices keep their true angles up to one turn; beyond, the fan is compressed to
// one turn (both boundary edges at angle 0) and its faces carry the excess as holonomy.
TEST(Connection, BoundaryFanKeepsItsTrueAnglesUpToOneTurn) {
  for (const double theta : {0.5 * kPi, kPi, 1.5 * kPi, 1.9 * kPi, 2 * kPi, 2.5 * kPi, 3 * kPi}) {
    SCOPED_TRACE(theta);
    const IntrinsicTriangulation tri = boundary_fan(theta, 12);
    const TangentFrames fr = tangent_frames(tri);
    const double scale = theta <= 2 * kPi ? 1.0 : 2 * kPi / theta;
    EXPECT_NEAR(fr.angle_sum[0], theta, 1e-12);
    EXPECT_NEAR(fr.angle_scale[0], scale, 1e-12);
    // the spokes at their (scaled) true angles from the outgoing boundary edge 0 → 1
    const Index h0 = tri.vertex_halfedge(0);
    ASSERT_EQ(tri.twin(h0), kInvalidIndex);
    Index x = h0;
    for (int i = 0; i < 12; ++i) {
      EXPECT_EQ(tri.head(x), i + 1);
      EXPECT_NEAR(wrapped(fr.halfedge_angle[x] - scale * theta * i / 12), 0.0, 1e-12) << i;
      if (i < 11) x = tri.twin(T::prev(x));
    }
    // the incoming boundary edge: at Θ (true), or back at 0 when compressed
    const double last = fr.halfedge_angle[x] + scale * intrinsic::corner_angle(tri, x);
    EXPECT_NEAR(wrapped(last - std::min(theta, 2 * kPi)), 0.0, 1e-12);
    // holonomy: none up to one turn, the excess 2π − Θ beyond
    const double expected = theta <= 2 * kPi ? 0.0 : 2 * kPi - theta;
    EXPECT_NEAR(wrapped(fr.holonomy_around(tri, 0) - expected), 0.0, 1e-10);
    for (Index f = 0; f < tri.n_faces(); ++f) {  // each face: its share (scale − 1)·Θ/k
      const Complex loop = fr.transport[3 * f] * fr.transport[3 * f + 1] * fr.transport[3 * f + 2];
      EXPECT_NEAR(wrapped(std::arg(loop) - expected / 12), 0.0, 1e-12) << f;
    }
    expect_matches_reference(tri, fr);
  }
}

// Flat domains whose boundary has corners (a jittered square; an L with its reflex corner at
// 3π/2, boundary vertices slid along their sides): no holonomy in any face, so a vector carried
// around any closed path comes back unchanged, and L is the scalar cotan Laplacian turned by a
// unit diagonal gauge (the same spectrum, with the negative weights of the non-Delaunay input).
TEST(Connection, FlatDomainsWithCornersHaveNoHolonomy) {
  for (const bool l_shape : {false, true}) {
    SCOPED_TRACE(l_shape);
    const TriangleMesh m = l_shape ? test::flat_l_shape(8, 0.3, 5) : test::flat_square(8, 0.3, 4);
    const IntrinsicTriangulation tri = from_mesh(m);
    const TangentFrames fr = tangent_frames(tri);
    const std::vector<char> boundary = boundary_vertices(tri);
    double min_theta = 10.0, max_theta = 0.0;
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      if (!boundary[v]) continue;
      EXPECT_EQ(fr.angle_scale[v], 1.0) << v;
      min_theta = std::min(min_theta, fr.angle_sum[v]);
      max_theta = std::max(max_theta, fr.angle_sum[v]);
    }
    EXPECT_NEAR(min_theta, kPi / 2, 1e-12);                    // the convex corners
    EXPECT_NEAR(max_theta, l_shape ? 1.5 * kPi : kPi, 1e-12);  // the reflex one, or the sides
    for (Index f = 0; f < tri.n_faces(); ++f) {
      const Complex loop = fr.transport[3 * f] * fr.transport[3 * f + 1] * fr.transport[3 * f + 2];
      EXPECT_LT(std::abs(loop - 1.0), 1e-13) << f;
    }
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      EXPECT_LT(std::abs(fr.holonomy_around(tri, v)), 1e-12) << v;
    }
    const Eigen::VectorXd mass = lumped_mass(tri);
    const Eigen::VectorXd ev = generalized_eigenvalues(dense(connection_laplacian(tri, fr)), mass);
    const Eigen::VectorXd scalar =
        generalized_eigenvalues(Eigen::MatrixXd(cotan_laplacian(tri)), mass);
    EXPECT_LT((ev - scalar).cwiseAbs().maxCoeff(), 1e-9 * scalar.maxCoeff());
    EXPECT_LT(std::abs(ev[0]), 1e-9 * scalar.maxCoeff());  // a parallel field: the constant
  }
}

TEST(Connection, SelfEdgeAddsItsHolonomyToTheDiagonal) {
  // Two triangles glued along all three sides (a sphere with three vertices) whose edge 0–1 is
  // too long to be Delaunay: the flip makes it a loop at vertex 2, with positive weight.
  // Vertex 3 is unreferenced.
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 2, 1}};
  Eigen::MatrixX3d l(2, 3);
  l << 1.9, 1.0, 1.1, 1.1, 1.0, 1.9;
  auto tri = IntrinsicTriangulation::from_side_lengths(f, 4, l);
  tri.flip_to_delaunay();
  const Eigen::VectorXd w = intrinsic::cotan_weights(tri);
  Index self = kInvalidIndex;
  for (Index e = 0; e < tri.n_edges(); ++e) {
    if (tri.tail(tri.edge_halfedge(e)) == tri.head(tri.edge_halfedge(e))) self = e;
  }
  ASSERT_NE(self, kInvalidIndex);
  ASSERT_GE(w.minCoeff(), 0.0);
  const TangentFrames fr = tangent_frames(tri);
  EXPECT_GT(std::abs(std::arg(fr.transport[tri.edge_halfedge(self)])), 1e-3);  // a real term
  expect_matches_reference(tri, fr);
  const ComplexSparseMatrix L = connection_laplacian(tri, fr);
  EXPECT_EQ(dense(L).row(3).cwiseAbs().sum() + dense(L).col(3).cwiseAbs().sum(), 0.0);
  EXPECT_EQ(fr.angle_sum[3], 0.0);
  EXPECT_EQ(fr.angle_scale[3], 0.0);
}

// Fans at each vertex of a closed triangulation: orbits of h ↦ twin(prev(h)) on its halfedges.
std::vector<int> fan_counts(const IntrinsicTriangulation& tri) {
  std::vector<int> fans(tri.n_vertices(), 0);
  std::vector<char> seen(tri.n_halfedges(), 0);
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    if (seen[h]) continue;
    ++fans[tri.tail(h)];
    for (Index x = h; !seen[x]; x = tri.twin(T::prev(x))) seen[x] = 1;
  }
  return fans;
}

// A nonmanifold soup: three fins on edge 0–1, a bowtie pinched at vertex 2 (faces 0-1-2 and
// 2-5-6 share only it), and an unreferenced vertex 7.
TriangleMesh fins_and_bowtie() {
  TriangleMesh m;
  m.positions.resize(8, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -0.5, 0.8, 0.5, -0.5, -0.8, 0, 2, 0.3, 1, 2.1,
      0.2, 9, 9, 9;
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {2, 5, 6}};
  return m;
}

// The intrinsic Delaunay tufted cover of faces: frames consistent fan by fan, L Hermitian PSD.
void expect_tufted_cover_works(const std::vector<Triangle>& faces, const Positions& positions,
                               bool pinched) {
  IntrinsicTriangulation tri = intrinsic::tufted_cover(faces, positions);
  tri.mollify();
  tri.flip_to_delaunay();
  const std::vector<int> fans = fan_counts(tri);
  ASSERT_EQ(*std::max_element(fans.begin(), fans.end()) > 1, pinched);
  {
    const TangentFrames fr = tangent_frames(tri);
    const Eigen::VectorXd theta = intrinsic::vertex_angle_sums(tri);
    // per vertex, (direction, scaled corner) of each outgoing halfedge, and the halfedges where
    // the counter-clockwise step rule breaks: at most one per fan, at its closing side
    std::vector<std::vector<std::pair<double, double>>> wedges(tri.n_vertices());
    std::vector<int> breaks(tri.n_vertices(), 0);
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      const Index v = tri.tail(h);
      const double step = fr.angle_scale[v] * intrinsic::corner_angle(tri, h);
      wedges[v].push_back({fr.halfedge_angle[h], step});
      const double next = fr.halfedge_angle[tri.twin(T::prev(h))];
      breaks[v] += std::abs(wrapped(next - fr.halfedge_angle[h] - step)) > 1e-12;
    }
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      EXPECT_NEAR(fr.angle_scale[v] * theta[v], theta[v] > 0 ? 2 * kPi : 0.0, 1e-12);
      EXPECT_LE(breaks[v], fans[v] > 1 ? fans[v] : 0) << v;
      // the fans, one after the other, tile [0, 2π) without overlap
      std::sort(wedges[v].begin(), wedges[v].end());
      double end = 0.0;
      for (const auto& [angle, step] : wedges[v]) {
        EXPECT_NEAR(angle, end, 1e-12) << v;
        end = angle + step;
      }
      if (!wedges[v].empty()) {
        EXPECT_NEAR(end, 2 * kPi, 1e-12) << v;
      }
    }
    for (Index h = 0; h < tri.n_halfedges(); ++h) {
      EXPECT_TRUE(fr.halfedge_angle[h] >= 0.0 && fr.halfedge_angle[h] < 2 * kPi);
      EXPECT_LT(std::abs(fr.transport[h] * fr.transport[tri.twin(h)] - 1.0), 1e-14);
    }
    expect_matches_reference(tri, fr);
  }
}

TEST(Connection, TuftedCoverOfNonmanifoldMeshes) {
  // fan3: three faces on one edge, one fan per vertex in the cover; the soup and a manifold
  // square: pinched (the cover of an interior vertex has a front and a back fan)
  const io::SurfaceInput fan3 = io::read_mesh((test::test_data() / "fan3.obj").string());
  expect_tufted_cover_works(fan3.triangles, fan3.positions, false);
  const TriangleMesh soup = fins_and_bowtie();
  expect_tufted_cover_works(soup.faces, soup.positions, true);
  const TriangleMesh square = bumpy_grid(4);
  expect_tufted_cover_works(square.faces, square.positions, true);
}

}  // namespace
}  // namespace ifem::fem
