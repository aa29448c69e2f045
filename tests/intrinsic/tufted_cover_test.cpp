#include "intrinsic/surface/tufted_cover.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "support/dense_spectrum.h"

namespace ifem::intrinsic {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// Reference operators assembled the textbook way from cotan weights (triplets), divided by the
// multiplicity: an oracle independent of fem/.
struct Ops {
  Sparse L;
  Eigen::VectorXd m;
};

Ops operators(const IntrinsicTriangulation& tri) {
  const Eigen::VectorXd w = cotan_weights(tri);
  std::vector<Eigen::Triplet<double>> t;
  const double s = 1.0 / tri.multiplicity();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const Index h = tri.edge_halfedge(e);
    const Index i = tri.tail(h), j = tri.head(h);
    if (i == j) continue;
    t.emplace_back(i, j, -s * w[e]);
    t.emplace_back(j, i, -s * w[e]);
    t.emplace_back(i, i, s * w[e]);
    t.emplace_back(j, j, s * w[e]);
  }
  Ops o;
  o.L.resize(tri.n_vertices(), tri.n_vertices());
  o.L.setFromTriplets(t.begin(), t.end());
  o.m = Eigen::VectorXd::Zero(tri.n_vertices());
  for (Index f = 0; f < tri.n_faces(); ++f) {
    for (int k = 0; k < 3; ++k) o.m[tri.tail(3 * f + k)] += s * face_area(tri, f) / 3.0;
  }
  return o;
}

Ops tufted_idt(const std::vector<Triangle>& faces, const Positions& p,
               TuftedCoverReport* rep = nullptr) {
  IntrinsicTriangulation tri = tufted_cover(faces, p, rep);
  tri.mollify();
  const FlipReport fr = tri.flip_to_delaunay();
  EXPECT_FALSE(fr.hit_flip_cap);
  return operators(tri);
}

double max_abs(const Sparse& A) {
  double m = 0;
  for (int k = 0; k < A.outerSize(); ++k) {
    for (Sparse::InnerIterator it(A, k); it; ++it) m = std::max(m, std::abs(it.value()));
  }
  return m;
}

// Smallest `count` eigenvalues of L φ = λ M φ restricted to vertices with positive mass
// (M is diagonal: the symmetric scaling M^{-1/2} L M^{-1/2} has the same spectrum).
Eigen::VectorXd low_spectrum(const Ops& o, int count) {
  std::vector<Index> keep;
  for (Index i = 0; i < o.m.size(); ++i) {
    if (o.m[i] > 0) keep.push_back(i);
  }
  const Eigen::MatrixXd full = Eigen::MatrixXd(o.L);
  const Index n = static_cast<Index>(keep.size());
  Eigen::MatrixXd A(n, n);
  for (Index a = 0; a < n; ++a) {
    for (Index b = 0; b < n; ++b) {
      A(a, b) = full(keep[a], keep[b]) / std::sqrt(o.m[keep[a]] * o.m[keep[b]]);
    }
  }
  return test::self_adjoint_eigenvalues(A).head(std::min<Index>(count, n));
}

void expect_same_spectrum(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double rel) {
  ASSERT_EQ(a.size(), b.size());
  const double scale = std::max(a.cwiseAbs().maxCoeff(), 1e-300);
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i], b[i], rel * std::max(std::abs(a[i]), 1e-6 * scale)) << "eigenvalue " << i;
  }
}

void expect_good_laplacian(const Ops& o, const std::vector<Triangle>& faces,
                           const std::string& what) {
  const Index n = static_cast<Index>(o.L.rows());
  ASSERT_EQ(o.m.size(), n);
  double scale = 0;
  for (int k = 0; k < o.L.outerSize(); ++k) {
    for (Sparse::InnerIterator it(o.L, k); it; ++it) {
      ASSERT_TRUE(std::isfinite(it.value())) << what;
      scale = std::max(scale, std::abs(it.value()));
    }
  }
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(n);
  EXPECT_LE((o.L * ones).cwiseAbs().maxCoeff(), 1e-10 * std::max(scale, 1e-300)) << what;
  const Sparse asym = Sparse(o.L.transpose()) - o.L;
  EXPECT_LE(asym.cwiseAbs().sum(), 1e-12 * std::max(scale, 1e-300) * n) << what;
  for (int k = 0; k < o.L.outerSize(); ++k) {
    for (Sparse::InnerIterator it(o.L, k); it; ++it) {
      if (it.row() != it.col()) {
        EXPECT_LE(it.value(), 1e-10 * scale) << what << " entry " << it.row() << "," << it.col();
      }
    }
  }
  std::vector<char> used(n, 0);
  for (const Triangle& t : faces) {
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  }
  for (Index i = 0; i < n; ++i) {
    ASSERT_TRUE(std::isfinite(o.m[i])) << what;
    if (used[i])
      EXPECT_GT(o.m[i], 0.0) << what << " vertex " << i;
    else
      EXPECT_EQ(o.m[i], 0.0) << what << " vertex " << i;
  }
}

// The same faces in another order, each with its corners rotated and, when `reverse`,
// reversed: the cover (and so L, M) must not change beyond rounding.
std::vector<Triangle> shuffled(std::vector<Triangle> faces, unsigned seed, bool reverse) {
  std::mt19937 rng(seed);
  std::shuffle(faces.begin(), faces.end(), rng);
  for (Triangle& t : faces) {
    std::rotate(t.begin(), t.begin() + rng() % 3, t.end());
    if (reverse && rng() % 2) std::swap(t[1], t[2]);
  }
  return faces;
}

Positions to_positions(std::initializer_list<std::array<double, 3>> pts) {
  Positions p(static_cast<Eigen::Index>(pts.size()), 3);
  Eigen::Index i = 0;
  for (const auto& x : pts) p.row(i++) << x[0], x[1], x[2];
  return p;
}

// ------------------------------------------------------------------------------------------

TEST(TuftedCover, Fan3IsClosedEdgeManifold) {
  // three triangles on edge (0,1)
  const Positions p =
      to_positions({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -0.5, 0.8}, {0.5, -0.5, -0.8}});
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 1, 3}, {1, 0, 4}};
  TuftedCoverReport rep;
  const IntrinsicTriangulation tri = tufted_cover(f, p, &rep);
  EXPECT_NO_THROW(tri.validate());
  EXPECT_EQ(tri.n_faces(), 6);
  EXPECT_EQ(tri.multiplicity(), 2);
  EXPECT_FALSE(tri.has_boundary());
  EXPECT_EQ(rep.nonmanifold_edges, 1);
  EXPECT_EQ(rep.max_faces_per_edge, 3);
  EXPECT_EQ(rep.boundary_edges, 6);
  EXPECT_EQ(rep.first_nonmanifold_edge[0], 0);
  EXPECT_EQ(rep.first_nonmanifold_edge[1], 1);
  ASSERT_EQ(rep.parent_face.size(), 6u);
  EXPECT_EQ(rep.parent_face[4], 2);
  // every cover edge has exactly two sides, so the halfedge count is twice the edge count
  EXPECT_EQ(tri.n_halfedges(), 2 * tri.n_edges());
  EXPECT_NEAR(total_area(tri), 0.5 + std::hypot(0.5, 0.8), 1e-12);
}

TEST(TuftedCover, AngularOrderAroundEdge) {
  // four half-planes around the x axis at angles 0°, 90°, 180°, 270°, listed out of order:
  // copies must be glued between angular neighbours only (a planar pair 0°/180° forms a flat
  // sheet with the two others as fins, whatever the listing order)
  // vertex ids deliberately not in angular order: 2 at 0°, 3 at 180°, 4 at 90°, 5 at 270°
  const Positions p =
      to_positions({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}, {0.5, 0, -1}});
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 1, 4}, {0, 1, 3}, {0, 1, 5}};
  TuftedCoverReport rep;
  const IntrinsicTriangulation tri = tufted_cover(f, p, &rep);
  tri.validate();
  // for each cover halfedge along (0,1), the opposite vertex across the glued side must be an
  // angular neighbour (not the opposite one)
  int checked = 0;
  for (Index h = 0; h < tri.n_halfedges(); ++h) {
    const Index a = tri.tail(h), b = tri.head(h);
    if (!((a == 0 && b == 1) || (a == 1 && b == 0))) continue;
    const Index c = tri.tail(IntrinsicTriangulation::prev(h));
    const Index d = tri.tail(IntrinsicTriangulation::prev(tri.twin(h)));
    const int quadrant[4] = {0, 2, 1, 3};
    const int ic = quadrant[c - 2], id = quadrant[d - 2];
    EXPECT_TRUE((ic - id + 4) % 4 == 1 || (id - ic + 4) % 4 == 1) << c << " glued to " << d;
    ++checked;
  }
  EXPECT_EQ(checked, 8);
}

TEST(TuftedCover, ManifoldMeshGivesTheManifoldLaplacian) {
  // Closed mesh: the cover is two copies, multiplicity 2 halves the doubled weights, so
  // L_tufted = L_manifold and M_tufted = M_manifold exactly, after intrinsic Delaunay too.
  const TriangleMesh m = test::jittered(icosphere(5), 0.04, 3);
  IntrinsicTriangulation man = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  man.mollify();
  man.flip_to_delaunay();
  const Ops a = operators(man);
  const Ops b = tufted_idt(m.faces, m.positions);
  const double scale = max_abs(a.L);
  EXPECT_LE(max_abs(Sparse(a.L - b.L)), 1e-10 * scale);
  EXPECT_LE((a.m - b.m).cwiseAbs().maxCoeff(), 1e-12 * a.m.maxCoeff());
  expect_same_spectrum(low_spectrum(a, 20), low_spectrum(b, 20), 1e-8);
}

TEST(TuftedCover, BoundaryMeshBeforeFlipsMatchesManifold) {
  // With boundary, the cover zips front and back: before flips the operators agree (a boundary
  // edge gets cot α from each copy, halved); after intrinsic Delaunay the cover may flip the
  // zipped edges, which the manifold path keeps, so only the low spectra stay close.
  const TriangleMesh m = test::jittered(grid(12, 10), 0.03, 5);
  const IntrinsicTriangulation man = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const IntrinsicTriangulation cov = tufted_cover(m.faces, m.positions);
  const Ops a = operators(man), b = operators(cov);
  const double scale = max_abs(a.L);
  EXPECT_LE(max_abs(Sparse(a.L - b.L)), 1e-12 * scale);
  EXPECT_LE((a.m - b.m).cwiseAbs().maxCoeff(), 1e-14);
  IntrinsicTriangulation man2 = man;
  man2.flip_to_delaunay();
  const Eigen::VectorXd sa = low_spectrum(operators(man2), 6);
  const Eigen::VectorXd sb = low_spectrum(tufted_idt(m.faces, m.positions), 6);
  for (int i = 1; i < 6; ++i) EXPECT_NEAR(sa[i], sb[i], 0.05 * sa[i]);
}

TEST(TuftedCover, DegenerateInputs) {
  // duplicate faces, a face repeating a vertex, a zero-area face, coincident vertices 5 = 1,
  // an unreferenced vertex 6, inconsistent orientation, a nonmanifold edge
  const Positions p = to_positions({{0, 0, 0},
                                    {1, 0, 0},
                                    {0, 1, 0},
                                    {1, 1, 0.2},
                                    {2, 0, 0},
                                    {1, 0, 0},
                                    {9, 9, 9},
                                    {0.3, -1, 0.4}});
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 1, 2}, {2, 1, 0},
                                   {1, 3, 2}, {2, 2, 3}, {0, 1, 4},  // zero area: 0, 1, 4 collinear
                                   {5, 3, 1},  // 5 coincides with 1: a zero-length side
                                   {1, 0, 7}};
  TuftedCoverReport rep;
  IntrinsicTriangulation tri = tufted_cover(f, p, &rep);
  EXPECT_EQ(rep.dropped_faces, 1);
  EXPECT_EQ(rep.unreferenced_vertices, 1);
  EXPECT_GE(rep.nonmanifold_edges, 1);
  EXPECT_EQ(tri.n_faces(), 14);
  EXPECT_EQ(tri.vertex_halfedge(6), kInvalidIndex);
  const MollifyReport mr = tri.mollify();
  EXPECT_GT(mr.delta, 0.0);
  tri.validate();
  tri.flip_to_delaunay();
  tri.validate();
  const Ops o = operators(tri);
  expect_good_laplacian(o, f, "degenerate");
  EXPECT_EQ(o.L.col(6).cwiseAbs().sum(), 0.0);
  EXPECT_EQ(o.m[6], 0.0);
}

TEST(TuftedCover, EmptyAndAllDropped) {
  const Positions p = to_positions({{0, 0, 0}, {1, 0, 0}});
  TuftedCoverReport rep;
  const IntrinsicTriangulation tri = tufted_cover({{0, 1, 1}}, p, &rep);
  EXPECT_EQ(tri.n_faces(), 0);
  EXPECT_EQ(tri.n_vertices(), 2);
  EXPECT_EQ(rep.dropped_faces, 1);
  EXPECT_EQ(rep.unreferenced_vertices, 2);
  EXPECT_THROW(tufted_cover({{0, 1, 2}}, p), InvalidInput);
  Positions bad = p;
  bad(1, 0) = std::nan("");
  EXPECT_THROW(tufted_cover({{0, 1, 0}}, bad), InvalidInput);
}

TEST(TuftedCover, FromSideLengths) {
  const TriangleMesh m = test::jittered(icosphere(2), 0.05, 9);
  Eigen::MatrixX3d side(m.faces.size(), 3);
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    for (int s = 0; s < 3; ++s) {
      side(f, s) =
          (m.positions.row(m.faces[f][s]) - m.positions.row(m.faces[f][(s + 1) % 3])).norm();
    }
  }
  std::vector<Triangle> faces = m.faces;
  faces.push_back(m.faces[0]);  // a nonmanifold edge by duplication
  Eigen::MatrixX3d side2(side.rows() + 1, 3);
  side2 << side, side.row(0);
  const Ops a = tufted_idt(faces, m.positions);
  IntrinsicTriangulation tri = tufted_cover(faces, static_cast<Index>(m.positions.rows()), side2);
  tri.mollify();
  tri.flip_to_delaunay();
  const Ops b = operators(tri);
  expect_same_spectrum(low_spectrum(a, 30), low_spectrum(b, 30), 1e-8);
  side2(0, 0) *= 1.5;  // glued sides disagree
  EXPECT_THROW(tufted_cover(faces, static_cast<Index>(m.positions.rows()), side2), InvalidInput);
}

TEST(TuftedCover, FaceOrderInvarianceSynthetic) {
  // a tangle of nonmanifold fins and duplicates over a jittered sphere
  TriangleMesh m = test::jittered(icosphere(3), 0.03, 11);
  const std::size_t nf = m.faces.size();
  for (std::size_t f = 0; f < nf; f += 7) {
    const Triangle t = m.faces[f];
    const Index nv = static_cast<Index>(m.positions.rows());
    m.positions.conservativeResize(nv + 1, 3);
    m.positions.row(nv) = 1.4 * m.positions.row(t[0]);  // a fin sticking out of edge (t0, t1)
    m.faces.push_back({t[0], t[1], nv});
    if (f % 3 == 0) m.faces.push_back({t[2], t[1], t[0]});  // a duplicate, reversed
  }
  const Ops a = tufted_idt(m.faces, m.positions);
  expect_good_laplacian(a, m.faces, "fins");
  const Eigen::VectorXd sa = low_spectrum(a, 1 << 20);
  for (unsigned seed : {1u, 2u, 3u}) {
    const Ops b = tufted_idt(shuffled(m.faces, seed, true), m.positions);
    expect_same_spectrum(sa, low_spectrum(b, 1 << 20), 1e-8);
    const double scale = max_abs(a.L);
    EXPECT_LE(max_abs(Sparse(a.L - b.L)), 1e-9 * scale);
  }
}

// ---- the shared corpus ----------------------------------------------------------------------

TEST(TuftedCoverData, EveryMeshGivesAGoodLaplacian) {
  IFEM_REQUIRE_SHARED_DATA();
  int n = 0;
  for (const auto& file : test::shared_files("meshes")) {
    SCOPED_TRACE(file.filename().string());
    if (test::skip_in_quick_run(file)) continue;
    const io::SurfaceInput in = io::read_surface(file.string());
    TuftedCoverReport rep;
    const Ops o = tufted_idt(in.triangles, in.positions, &rep);
    expect_good_laplacian(o, in.triangles, file.filename().string());
    ++n;
  }
  EXPECT_GE(n, 30);
}

TEST(TuftedCoverData, NonmanifoldMeshesAreFaceOrderInvariant) {
  IFEM_REQUIRE_SHARED_DATA();
  for (const char* name :
       {"fan3.obj", "triple_vierbein.obj", "beetle_sutherland.obj", "truck.obj", "conrod.off",
        "thingi10k_138207.obj", "thingi10k_49220.obj", "thingi10k_73342.obj", "thingi10k_90225.obj",
        "moebius.obj", "cgal_all_degen.off", "cgal_degtri_nullface_bis.off",
        "cgal_fused_vertices.off", "cgal_non_manifold_face_graph.off", "hourglass_ico.obj"}) {
    SCOPED_TRACE(name);
    const auto file = test::shared_data() / "meshes" / name;
    const io::SurfaceInput in = io::read_surface(file.string());
    TuftedCoverReport rep;
    const Ops a = tufted_idt(in.triangles, in.positions, &rep);
    const Ops b = tufted_idt(shuffled(in.triangles, 7, true), in.positions);
    const double scale = max_abs(a.L);
    EXPECT_LE(max_abs(Sparse(a.L - b.L)), 1e-9 * scale);
    EXPECT_LE((a.m - b.m).cwiseAbs().maxCoeff(), 1e-9 * a.m.maxCoeff());
    if (in.positions.rows() <= 1200) {
      expect_same_spectrum(low_spectrum(a, 1 << 20), low_spectrum(b, 1 << 20), 1e-8);
    }
  }
}

}  // namespace
}  // namespace ifem::intrinsic
