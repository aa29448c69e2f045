// Intrinsic simplification (intrinsic/simplify/simplify.h) and its prolongation
// (fem/prolongation.h): invariants after every removal, the tracked points, boundary, several
// components, the tufted cover, repeated coarsening, refusals, and the sphere's spectrum.
#include "intrinsic/simplify/simplify.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numeric>
#include <queue>
#include <random>

#include "fem/connection.h"
#include "fem/operators.h"
#include "fem/prolongation.h"
#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/union_find.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/surface/tufted_cover.h"
#include "pointcloud/pointcloud_laplacian.h"
#include "solvers/scalar/eigen.h"

namespace ifem::intrinsic {
namespace {

using intrinsic::kPi;

IntrinsicTriangulation mesh_of(const TriangleMesh& m) {
  return IntrinsicTriangulation::from_positions(m.faces, m.positions);
}

// Boundary loops of a triangulation: boundary sides joined head to tail.
Index boundary_loops(const IntrinsicTriangulation& tri) {
  std::vector<Index> sides;
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    if (tri.twin(h) == kInvalidIndex) sides.push_back(h);
  }
  UnionFind uf(tri.n_vertices());
  for (Index h : sides) uf.unite(tri.tail(h), tri.head(h));
  std::vector<char> root(tri.n_vertices(), 0);
  Index loops = 0;
  for (Index h : sides) {
    const Index r = uf.find(tri.tail(h));
    if (!root[r]) root[r] = 1, ++loops;
  }
  return loops;
}

Index components(const IntrinsicTriangulation& tri) {
  UnionFind uf(tri.n_vertices());
  for (Index h = 0; h < tri.n_halfedges(); ++h) uf.unite(tri.tail(h), tri.head(h));
  Index n = 0;
  for (Index v = 0; v < tri.n_vertices(); ++v) {
    if (tri.vertex_halfedge(v) != kInvalidIndex && uf.find(v) == v) ++n;
  }
  return n;
}

// Everything simplify.h promises about one result (Euler characteristic and component count
// only when asked: removing a vertex with two fans changes them).
void check(const IntrinsicTriangulation& fine, const Simplification& s, bool same_euler = true) {
  ASSERT_NO_THROW(s.coarse.validate());
  EXPECT_EQ(s.coarse.n_vertices(), Index(s.coarse_to_fine.size()));
  EXPECT_EQ(s.coarse.multiplicity(), fine.multiplicity());
  if (same_euler) {
    EXPECT_EQ(euler_characteristic(s.coarse), euler_characteristic(fine));
    EXPECT_NEAR(angle_defects(s.coarse).sum(), 2.0 * kPi * double(euler_characteristic(fine)),
                1e-9);
  }
  EXPECT_NEAR(total_area(s.coarse), total_area(fine), 1e-12 * total_area(fine));
  EXPECT_EQ(boundary_loops(s.coarse), boundary_loops(fine));
  if (same_euler) {  // a pinch can split
    EXPECT_EQ(components(s.coarse), components(fine));
  }
  ASSERT_EQ(Index(s.fine_in_coarse.size()), fine.n_vertices());
  for (Index v = 0; v < fine.n_vertices(); ++v) {
    const SurfacePoint& p = s.fine_in_coarse[v];
    if (fine.vertex_halfedge(v) == kInvalidIndex) {  // unreferenced: kept, no face
      EXPECT_EQ(p.face, kInvalidIndex);
      continue;
    }
    ASSERT_GE(p.face, 0);
    ASSERT_LT(p.face, s.coarse.n_faces());
    EXPECT_GE(p.bary.minCoeff(), 0.0);
    EXPECT_NEAR(p.bary.sum(), 1.0, 1e-12);
  }
  for (Index c = 0; c < s.coarse.n_vertices(); ++c) {
    const SurfacePoint& p = s.fine_in_coarse[s.coarse_to_fine[c]];  // a corner, coordinate 1
    if (p.face == kInvalidIndex) continue;
    double at_c = 0.0;
    for (int k = 0; k < 3; ++k) at_c += s.coarse.tail(3 * p.face + k) == c ? p.bary[k] : 0.0;
    EXPECT_EQ(at_c, 1.0);
  }
  const fem::SparseMatrix P = fem::prolongation(s);
  ASSERT_EQ(P.rows(), fine.n_vertices());
  ASSERT_EQ(P.cols(), s.coarse.n_vertices());
  const Eigen::VectorXd rows = P * Eigen::VectorXd::Ones(P.cols());
  EXPECT_LT((rows.array() - 1.0).abs().maxCoeff(), 1e-12);
  for (int k = 0; k < P.outerSize(); ++k) {
    for (fem::SparseMatrix::InnerIterator it(P, k); it; ++it) EXPECT_GE(it.value(), 0.0);
  }
}

SimplifyOptions to(Index n) {
  SimplifyOptions o;
  o.target_vertices = n;
  return o;
}

TEST(Simplify, IcosphereEveryRemoval) {
  const IntrinsicTriangulation fine = mesh_of(icosphere(3));  // 92 vertices
  for (Index n = fine.n_vertices() - 1; n >= 4; --n) {
    SCOPED_TRACE(n);
    const Simplification s = simplify(fine, to(n));
    EXPECT_EQ(s.coarse.n_vertices(), n);
    EXPECT_EQ(s.report.removals, fine.n_vertices() - n);
    EXPECT_EQ(s.report.stuck, 0);
    check(fine, s);
  }
}

TEST(Simplify, BoundaryEveryRemoval) {
  const IntrinsicTriangulation fine = mesh_of(grid(6, 5));  // 42 vertices, one loop
  Index last = fine.n_vertices();
  for (Index n = fine.n_vertices() - 1; n >= 3; --n) {
    SCOPED_TRACE(n);
    const Simplification s = simplify(fine, to(n));
    check(fine, s);
    EXPECT_LE(s.coarse.n_vertices(), last);
    last = s.coarse.n_vertices();
  }
  EXPECT_GT(simplify(fine, to(3)).report.boundary_removals, 0);
}

// A flat torus (a periodic grid): every vertex is flat, so every removal keeps the metric and
// the area exactly, before any rescale.
TEST(Simplify, FlatTorusIsExact) {
  const int n = 12;
  std::vector<Triangle> faces;
  Eigen::MatrixX3d lengths;
  auto id = [&](int i, int j) { return Index(((i + n) % n) * n + (j + n) % n); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  lengths.resize(Index(faces.size()), 3);
  for (Index f = 0; f < Index(faces.size()); ++f) {
    lengths.row(f) = f % 2 == 0 ? Eigen::RowVector3d(1.0, 1.0, std::sqrt(2.0))
                                : Eigen::RowVector3d(std::sqrt(2.0), 1.0, 1.0);
  }
  const auto fine = IntrinsicTriangulation::from_side_lengths(faces, n * n, lengths);
  const Simplification s = simplify(fine, to(20));
  EXPECT_EQ(s.coarse.n_vertices(), 20);
  EXPECT_LT(s.report.area_change_before_rescale, 1e-12);
  EXPECT_LT(angle_defects(s.coarse).cwiseAbs().maxCoeff(), 1e-9);
  check(fine, s);
}

TEST(Simplify, SeveralComponents) {
  TriangleMesh a = icosphere(4), b = grid(8, 8), c = torus_knot_tube(30, 6, 0.3);
  TriangleMesh all;
  all.positions.resize(a.positions.rows() + b.positions.rows() + c.positions.rows(), 3);
  all.positions << a.positions, b.positions, c.positions;
  all.faces = a.faces;
  for (auto t : b.faces)
    all.faces.push_back({t[0] + Index(a.positions.rows()), t[1] + Index(a.positions.rows()),
                         t[2] + Index(a.positions.rows())});
  const Index off = Index(a.positions.rows() + b.positions.rows());
  for (auto t : c.faces) all.faces.push_back({t[0] + off, t[1] + off, t[2] + off});
  const IntrinsicTriangulation fine = mesh_of(all);
  SimplifyOptions o;
  o.ratio = 0.05;
  const Simplification s = simplify(fine, o);
  check(fine, s);
  EXPECT_LE(s.coarse.n_vertices(),
            std::max<Index>(20, Index(0.05 * fine.n_vertices() + 1)) + s.report.stuck);
}

TEST(Simplify, TuftedCoverOfNonmanifoldMesh) {
  // a grid with a fin: three faces on its middle row's edges make them nonmanifold
  TriangleMesh m = grid(10, 10);
  const Index top = Index(m.positions.rows());
  m.positions.conservativeResize(top + 10, 3);
  for (int i = 0; i < 10; ++i) m.positions.row(top + i) << 0.1 * i + 0.05, 0.5, 0.3;
  for (int i = 0; i < 9; ++i) {
    const Index a = 5 * 11 + i, b = a + 1;  // row 5 of the 11×11 vertex grid
    m.faces.push_back({a, b, top + i});
  }
  const IntrinsicTriangulation fine = tufted_cover(m.faces, m.positions);
  ASSERT_EQ(fine.multiplicity(), 2);
  SimplifyOptions o;
  o.ratio = 0.3;
  const Simplification s = simplify(fine, o);
  EXPECT_LT(s.coarse.n_vertices(), fine.n_vertices() / 2);
  check(fine, s, /*same_euler=*/false);
  // the cover keeps faces in pairs, so its coarse Laplacian still has a constant null vector
  const fem::SparseMatrix L = fem::cotan_laplacian(s.coarse);
  EXPECT_LT((L * Eigen::VectorXd::Ones(L.cols())).cwiseAbs().maxCoeff(), 1e-9);
}

// A point cloud's triangulation (local triangulations merged, tufted, its vertices with many
// fans, some wound around the point more than once, self-edges): simplified close to the target
// by flattening, deleting pillows and flipping self-edges away, every invariant kept.
// Point clouds reach the target: the cover built without self-edges (PointCloudOptions::
// self_edges = false, as `ifem simplify` builds it), pillows of any size deleted, a point
// whose fans are all pillows removed (D-345). Clouds of several shapes: a sphere, a jittered
// sphere (irregular stars), the knot tube's vertices (thin, curved), a range scan's vertices
// (holes, needle rims, islands).
TEST(Simplify, PointCloudReachesItsTarget) {
  RangeScanOptions scan;
  scan.nx = scan.ny = 24;
  TriangleMesh jittered = icosphere(9);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  for (Index v = 0; v < Index(jittered.positions.rows()); ++v) {
    for (int c = 0; c < 3; ++c) jittered.positions(v, c) += u(rng);
  }
  const std::pair<Positions, double> clouds[] = {{icosphere(8).positions, 0.3},
                                                 {icosphere(11).positions, 0.1},
                                                 {jittered.positions, 0.1},
                                                 {torus_knot_tube(60, 8).positions, 0.2},
                                                 {range_scan(scan).positions, 0.1}};
  pointcloud::PointCloudOptions po;
  po.self_edges = false;
  for (const auto& [points, ratio] : clouds) {
    const IntrinsicTriangulation fine = pointcloud::pointcloud_triangulation(points, po);
    SimplifyOptions o;
    o.ratio = ratio;
    const Simplification s = simplify(fine, o);
    check(fine, s, /*same_euler=*/false);
    const Index target = Index(std::llround(ratio * double(fine.n_vertices())));
    SCOPED_TRACE(std::to_string(fine.n_vertices()) + " points, ratio " + std::to_string(ratio));
    EXPECT_EQ(s.coarse.n_vertices(), target);
    EXPECT_EQ(s.report.stuck, 0);
    EXPECT_GT(s.report.flattened, 0);
  }
}

// The tufted cover of a mesh with boundary: its boundary vertices have one closed fan that
// runs over the front and back copies (zipped), with every neighbour but two twice.
TEST(Simplify, TuftedCoverOfBoundary) {
  const TriangleMesh m = grid(12, 12);
  const IntrinsicTriangulation fine = tufted_cover(m.faces, m.positions);
  SimplifyOptions o;
  o.ratio = 0.2;
  const Simplification s = simplify(fine, o);
  EXPECT_LE(s.coarse.n_vertices(), Index(0.2 * fine.n_vertices()) + s.report.stuck + 1);
  EXPECT_LT(s.coarse.n_vertices(), fine.n_vertices() / 3);
  check(fine, s, /*same_euler=*/false);
}

TEST(Simplify, RepeatedCoarseningKeepsBoundaryLoops) {
  TriangleMesh m = grid(30, 30);
  // punch two holes: drop the faces of two cells blocks
  std::vector<Triangle> kept;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Index cell = Index(f / 2), i = cell % 30, j = cell / 30;
    const bool hole =
        (i >= 5 && i < 9 && j >= 5 && j < 9) || (i >= 18 && i < 25 && j >= 14 && j < 20);
    if (!hole) kept.push_back(m.faces[f]);
  }
  IntrinsicTriangulation tri = IntrinsicTriangulation::from_positions(kept, m.positions);
  ASSERT_EQ(boundary_loops(tri), 3);
  SimplifyOptions o;
  o.ratio = 0.5;
  for (int level = 0; level < 6; ++level) {
    SCOPED_TRACE(level);
    Simplification s = simplify(tri, o);
    check(tri, s);
    tri = std::move(s.coarse);
  }
  Index referenced = 0;  // the holes' inner grid vertices stay, unreferenced
  for (Index v = 0; v < tri.n_vertices(); ++v)
    referenced += tri.vertex_halfedge(v) != kInvalidIndex;
  EXPECT_LT(referenced, 100);  // from 922: the boundary loops and their corners stay
}

// Hard inputs at several ratios: a sliver tube, and a range scan (holes, pinched vertices,
// needle rims, islands) on both paths.
// The removal order breaks cost ties by the faces' breadth-first order (D-340), not by vertex
// ids: the same mesh with its vertices renumbered simplifies to the same coarse triangulation
// (renumbered alike), bit for bit. On the exact icosphere many costs tie.
TEST(Simplify, VertexNumberingDoesNotChangeTheResult) {
  const TriangleMesh m = icosphere(10);  // 1,002 vertices
  const Index nv = Index(m.positions.rows());
  std::vector<Index> perm(nv);  // input vertex v is vertex perm[v] of the renumbered mesh
  std::iota(perm.begin(), perm.end(), 0);
  std::reverse(perm.begin(), perm.end());
  std::swap(perm[3], perm[500]);
  TriangleMesh r = m;
  for (Index v = 0; v < nv; ++v) r.positions.row(perm[v]) = m.positions.row(v);
  for (auto& f : r.faces) {
    for (auto& c : f) c = perm[c];
  }
  const Simplification a = simplify(mesh_of(m), to(100)), b = simplify(mesh_of(r), to(100));
  ASSERT_EQ(a.coarse.n_faces(), b.coarse.n_faces());
  for (Index h = 0; h < a.coarse.n_halfedges(); ++h) {
    EXPECT_EQ(perm[a.coarse_to_fine[a.coarse.tail(h)]], b.coarse_to_fine[b.coarse.tail(h)]);
    EXPECT_EQ(a.coarse.twin(h), b.coarse.twin(h));
    EXPECT_EQ(a.coarse.halfedge_length(h), b.coarse.halfedge_length(h));
  }
  for (Index v = 0; v < nv; ++v) {
    EXPECT_EQ(a.fine_in_coarse[v].face, b.fine_in_coarse[perm[v]].face);
    EXPECT_EQ(a.fine_in_coarse[v].bary, b.fine_in_coarse[perm[v]].bary);
  }
}

TEST(Simplify, SliversAndScans) {
  RangeScanOptions scan;
  scan.nx = scan.ny = 30;
  const TriangleMesh tube = torus_knot_tube(100, 8), rs = range_scan(scan);
  const IntrinsicTriangulation inputs[] = {mesh_of(tube), mesh_of(rs),
                                           tufted_cover(rs.faces, rs.positions)};
  for (const auto& fine : inputs) {
    for (double ratio : {0.5, 0.1, 0.02}) {
      SCOPED_TRACE(std::to_string(fine.multiplicity()) + " " + std::to_string(fine.n_faces()) +
                   " " + std::to_string(ratio));
      SimplifyOptions o;
      o.ratio = ratio;
      const Simplification s = simplify(fine, o);
      check(fine, s, fine.multiplicity() == 1);
      EXPECT_LT(s.coarse.n_vertices(), fine.n_vertices());
    }
  }
}

TEST(Simplify, RefusesBadOptions) {
  const IntrinsicTriangulation fine = mesh_of(icosphere(2));
  SimplifyOptions o;
  EXPECT_THROW(simplify(fine, o), InvalidInput);  // neither set
  o.ratio = 0.0;
  o.target_vertices = fine.n_vertices();
  try {
    simplify(fine, o);
    ADD_FAILURE() << "target = #V accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("target_vertices"), std::string::npos);
  }
  o.target_vertices = -3;
  EXPECT_THROW(simplify(fine, o), InvalidInput);
  o.target_vertices = 10;
  o.ratio = 0.5;
  EXPECT_THROW(simplify(fine, o), InvalidInput);  // both set
  o.target_vertices = 0;
  o.ratio = 1.5;
  EXPECT_THROW(simplify(fine, o), InvalidInput);
  o.ratio = 1.0;
  EXPECT_EQ(simplify(fine, o).coarse.n_vertices(), fine.n_vertices());
}

// Σ_k |P_ik| = 1 for every row of a tangent prolongation.
void expect_unit_rows(const fem::ComplexSparseMatrix& P) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(P.rows());
  for (int k = 0; k < P.outerSize(); ++k) {
    for (fem::ComplexSparseMatrix::InnerIterator it(P, k); it; ++it)
      sum[it.row()] += std::abs(it.value());
  }
  EXPECT_LT((sum.array() - 1.0).abs().maxCoeff(), 1e-12);
}

// A parallel field on a flat triangulation (trivial connection): 1 at vertex 0, carried along a
// breadth-first tree by the transport of fem/connection.h.
Eigen::VectorXcd parallel_field(const IntrinsicTriangulation& tri, const fem::TangentFrames& fr) {
  Eigen::VectorXcd z = Eigen::VectorXcd::Zero(tri.n_vertices());
  std::vector<char> seen(tri.n_vertices(), 0);
  std::vector<std::vector<Index>> out(tri.n_vertices());
  for (Index h = 0; h < tri.n_halfedges(); ++h) out[tri.tail(h)].push_back(h);
  std::queue<Index> q;
  q.push(0), seen[0] = 1, z[0] = 1.0;
  while (!q.empty()) {
    const Index i = q.front();
    q.pop();
    for (Index h : out[i]) {
      const Index j = tri.head(h);
      if (!seen[j]) seen[j] = 1, z[j] = fr.transport[h] * z[i], q.push(j);
    }
  }
  return z;
}

// Largest |z_j − r_h z_i| over the halfedges h = i→j: 0 for a parallel field.
double parallel_defect(const IntrinsicTriangulation& tri, const fem::TangentFrames& fr,
                       const Eigen::VectorXcd& z) {
  double worst = 0.0;
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    worst = std::max(worst, std::abs(z[tri.head(h)] - fr.transport[h] * z[tri.tail(h)]));
  }
  return worst;
}

// On a flat torus the connection is trivial: a parallel coarse field prolongs to a parallel
// fine field of unit length, exactly (the coarse faces are isometric to the fine ones).
TEST(Simplify, TangentProlongationKeepsParallelFieldsOnAFlatTorus) {
  for (const int n : {9, 12}) {
    std::vector<Triangle> faces;
    auto id = [&](int i, int j) { return Index(((i + n) % n) * n + (j + n) % n); };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
    Eigen::MatrixX3d lengths(Index(faces.size()), 3);
    for (Index f = 0; f < Index(faces.size()); ++f) {
      lengths.row(f) = f % 2 == 0 ? Eigen::RowVector3d(1.0, 1.0, std::sqrt(2.0))
                                  : Eigen::RowVector3d(std::sqrt(2.0), 1.0, 1.0);
    }
    const auto fine = IntrinsicTriangulation::from_side_lengths(faces, n * n, lengths);
    for (const Index target : {Index(n * n / 3), Index(20)}) {
      const Simplification s = simplify(fine, to(target));
      const fem::TangentFrames cf = fem::tangent_frames(s.coarse), ff = fem::tangent_frames(fine);
      const Eigen::VectorXcd u = parallel_field(s.coarse, cf);
      ASSERT_LT(parallel_defect(s.coarse, cf, u), 1e-9);  // the coarse torus is flat
      const fem::ComplexSparseMatrix P = fem::tangent_prolongation(fine, s);
      ASSERT_EQ(P.rows(), fine.n_vertices());
      ASSERT_EQ(P.cols(), s.coarse.n_vertices());
      expect_unit_rows(P);
      const Eigen::VectorXcd z = P * u;
      EXPECT_LT((z.cwiseAbs().array() - 1.0).abs().maxCoeff(), 1e-9) << n << " " << target;
      EXPECT_LT(parallel_defect(fine, ff, z), 1e-9) << n << " " << target;
      // the restriction is the adjoint: ⟨P u, z⟩ = ⟨u, Pᴴ z⟩
      const Eigen::VectorXcd r = P.adjoint() * z;
      EXPECT_NEAR(std::abs(u.dot(r) - (P * u).dot(z)), 0.0, 1e-9);
    }
  }
}

// The coordinate (fem/connection.h) at vertex v of tangent vector t, in 3D on the unit sphere:
// its angle from the tangent direction towards `toward` (the reference edge's far end), scaled.
std::complex<double> sphere_coordinate(const Eigen::Vector3d& x, const Eigen::Vector3d& toward,
                                       const Eigen::Vector3d& t, double scale) {
  const Eigen::Vector3d n = x.normalized();
  const Eigen::Vector3d e1 = (toward - x - (toward - x).dot(n) * n).normalized(), e2 = n.cross(e1);
  return std::polar(t.norm(), scale * std::atan2(t.dot(e2), t.dot(e1)));
}

// A rotation field on the unit sphere (e_z × x) from its coarse values: the prolonged field is
// the fine one up to the interpolation error, which shrinks as the coarse mesh is refined.
TEST(Simplify, TangentProlongationOfARotationFieldOnTheSphere) {
  const TriangleMesh m = icosphere(12);  // 1,442 vertices
  const IntrinsicTriangulation fine = mesh_of(m);
  const Eigen::Vector3d ez(0.0, 0.0, 1.0);
  auto field = [&](const IntrinsicTriangulation& tri, const std::vector<Index>& ids) {
    const fem::TangentFrames fr = fem::tangent_frames(tri);
    Eigen::VectorXcd z(tri.n_vertices());
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const Eigen::Vector3d x = m.positions.row(ids[v]).transpose();
      const Index far = ids[tri.head(tri.vertex_halfedge(v))];
      z[v] = sphere_coordinate(x, m.positions.row(far).transpose(), ez.cross(x), fr.angle_scale[v]);
    }
    return z;
  };
  std::vector<Index> identity(fine.n_vertices());
  std::iota(identity.begin(), identity.end(), Index(0));
  const Eigen::VectorXcd exact = field(fine, identity);
  double previous = HUGE_VAL;
  for (const Index target : {Index(150), Index(600)}) {
    const Simplification s = simplify(fine, to(target));
    const fem::ComplexSparseMatrix P = fem::tangent_prolongation(fine, s);
    expect_unit_rows(P);
    const Eigen::VectorXcd z = P * field(s.coarse, s.coarse_to_fine);
    std::vector<double> err(fine.n_vertices());
    for (Index v = 0; v < fine.n_vertices(); ++v) err[v] = std::abs(z[v] - exact[v]);
    std::sort(err.begin(), err.end());
    const double median = err[err.size() / 2], p95 = err[err.size() * 95 / 100];
    std::printf("coarse %d: median %.4f, 95%% %.4f, max %.4f of |field| <= 1\n", int(target),
                median, p95, err.back());
    EXPECT_LT(median, 0.05) << target;
    EXPECT_LT(p95, 0.15) << target;
    EXPECT_LT(median, previous) << target;
    previous = median;
  }
}

// The unit sphere's first 16 eigenvalues (0, 2 ×3, 6 ×5, 12 ×7) from the coarse operators.
TEST(Simplify, SphereSpectrum) {
  const IntrinsicTriangulation fine = mesh_of(icosphere(40));  // 16,002 vertices
  const Simplification s = simplify(fine, to(2000));
  check(fine, s);
  const auto coarse = solvers::eigenpairs(s.coarse, 16).values;
  const auto ref = solvers::eigenpairs(fine, 16).values;
  for (int k = 1; k < 16; ++k) {
    const int l = k < 4 ? 1 : k < 9 ? 2 : 3;
    EXPECT_NEAR(coarse[k], ref[k], 0.02 * ref[k]) << k;
    EXPECT_NEAR(coarse[k], l * (l + 1.0), 0.02 * l * (l + 1.0)) << k;
  }
}

}  // namespace
}  // namespace ifem::intrinsic
