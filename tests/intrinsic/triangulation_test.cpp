#include "intrinsic/core/triangulation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numeric>

#include "helpers.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"

namespace ifem::intrinsic {
namespace {

using test::jittered;

// Flips a copy and checks the invariants (tests/helpers.h); generated meshes here have no
// boundary edge facing an obtuse angle, so every weight must be non-negative.
void expect_flip_invariants(IntrinsicTriangulation tri) { test::check_flip_to_delaunay(tri, true); }

TEST(Triangulation, TetrahedronCounts) {
  const TriangleMesh m = tetrahedron();
  BuildReport rep;
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions, &rep);
  tri.validate();
  EXPECT_EQ(tri.n_vertices(), 4);
  EXPECT_EQ(tri.n_edges(), 6);
  EXPECT_EQ(tri.n_faces(), 4);
  EXPECT_FALSE(tri.has_boundary());
  EXPECT_EQ(euler_characteristic(tri), 2);
  EXPECT_EQ(rep.dropped_faces, 0);
  EXPECT_EQ(rep.reoriented_faces, 0);
  const double edge = std::sqrt(8.0 / 3.0);
  for (Index e = 0; e < 6; ++e) EXPECT_NEAR(tri.length(e), edge, 1e-14);
  EXPECT_NEAR(total_area(tri), 4 * std::sqrt(3.0) / 4 * edge * edge, 1e-12);
  EXPECT_NEAR(angle_defects(tri).sum(), 4 * kPi, 1e-12);
}

TEST(Triangulation, SkewedQuadFlipsExactlyOnce) {
  const TriangleMesh m = test::skewed_quad();
  auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  // the diagonal 0–2 is the only interior edge and it is not Delaunay
  Index diag = kInvalidIndex;
  for (Index e = 0; e < tri.n_edges(); ++e) {
    if (!tri.is_boundary_edge(e)) diag = e;
  }
  ASSERT_NE(diag, kInvalidIndex);
  EXPECT_FALSE(tri.is_delaunay(diag));
  const FlipReport rep = tri.flip_to_delaunay();
  EXPECT_EQ(rep.flips, 1u);
  tri.validate();
  // the new diagonal joins 1 and 3 with its Euclidean length
  const Index h = tri.edge_halfedge(diag);
  EXPECT_EQ(std::min(tri.tail(h), tri.head(h)), 1);
  EXPECT_EQ(std::max(tri.tail(h), tri.head(h)), 3);
  EXPECT_NEAR(tri.length(diag), (m.positions.row(1) - m.positions.row(3)).norm(), 1e-14);
  EXPECT_TRUE(tri.is_delaunay(diag));
  EXPECT_EQ(tri.flip_to_delaunay().flips, 0u);
}

TEST(Triangulation, FlipInvariantsOnGeneratedMeshes) {
  expect_flip_invariants(
      IntrinsicTriangulation::from_positions(icosphere(6).faces, icosphere(6).positions));
  const TriangleMesh s = jittered(icosphere(8), 0.08);
  expect_flip_invariants(IntrinsicTriangulation::from_positions(s.faces, s.positions));
  const TriangleMesh g = jittered(grid(12, 9), 0.05);
  expect_flip_invariants(IntrinsicTriangulation::from_positions(g.faces, g.positions));
  const TriangleMesh uv = jittered(uv_sphere(6, 80), 0.02);  // needle fans at the poles
  auto tri = IntrinsicTriangulation::from_positions(uv.faces, uv.positions);
  expect_flip_invariants(tri);
  EXPECT_GT(tri.flip_to_delaunay().flips, 0u);
}

TEST(Triangulation, FlippingTwiceRestoresLength) {
  const TriangleMesh s = jittered(icosphere(3), 0.05);
  auto tri = IntrinsicTriangulation::from_positions(s.faces, s.positions);
  for (Index e = 0; e < tri.n_edges(); e += 7) {
    const double before = tri.length(e);
    auto copy = tri;
    if (!copy.flip_edge(e)) continue;
    copy.validate();
    ASSERT_TRUE(copy.flip_edge(e));
    copy.validate();
    EXPECT_NEAR(copy.length(e), before, 1e-12 * before);
  }
}

TEST(Triangulation, GridWithBoundaryGaussBonnet) {
  const TriangleMesh g = grid(5, 4);
  const auto tri = IntrinsicTriangulation::from_positions(g.faces, g.positions);
  EXPECT_TRUE(tri.has_boundary());
  EXPECT_EQ(euler_characteristic(tri), 1);
  EXPECT_NEAR(angle_defects(tri).sum(), 2 * kPi, 1e-12);
  EXPECT_NEAR(total_area(tri), 1.0, 1e-14);
}

TEST(Triangulation, DropsFacesThatRepeatAVertex) {
  TriangleMesh m = tetrahedron();
  m.faces.push_back({0, 0, 1});
  m.faces.insert(m.faces.begin(), {2, 3, 2});
  BuildReport rep;
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions, &rep);
  EXPECT_EQ(rep.dropped_faces, 2);
  EXPECT_EQ(tri.n_faces(), 4);
  EXPECT_EQ(rep.face_origin, (std::vector<Index>{1, 2, 3, 4}));
}

TEST(Triangulation, KeepsUnreferencedVertices) {
  TriangleMesh m = tetrahedron();
  m.positions.conservativeResize(6, 3);
  m.positions.row(4) << 5, 5, 5;
  m.positions.row(5) << 6, 6, 6;
  BuildReport rep;
  auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions, &rep);
  EXPECT_EQ(tri.n_vertices(), 6);
  EXPECT_EQ(rep.unreferenced_vertices, 2);
  EXPECT_EQ(tri.vertex_halfedge(5), kInvalidIndex);
  tri.validate();
  // Gauss–Bonnet still holds: an isolated point is a component with χ = 1
  EXPECT_NEAR(angle_defects(tri).sum(), 2 * kPi * euler_characteristic(tri), 1e-12);
}

TEST(Triangulation, ReorientsInconsistentFaces) {
  TriangleMesh m = icosphere(2);
  for (std::size_t f = 0; f < m.faces.size(); f += 3) std::swap(m.faces[f][1], m.faces[f][2]);
  BuildReport rep;
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions, &rep);
  tri.validate();
  EXPECT_GT(rep.reoriented_faces, 0);
  EXPECT_EQ(euler_characteristic(tri), 2);
}

TEST(Triangulation, RejectsNonManifoldEdgeNamingIt) {
  const std::vector<Triangle> fan = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  Positions p = Positions::Random(5, 3);
  try {
    IntrinsicTriangulation::from_positions(fan, p);
    FAIL() << "expected NonManifoldInput";
  } catch (const NonManifoldInput& e) {
    EXPECT_NE(std::string(e.what()).find("edge (0,1) has 3 incident faces"), std::string::npos)
        << e.what();
  }
}

TEST(Triangulation, RejectsNonOrientableGluing) {
  // a Moebius strip: a band of 5 quads whose ends are glued with a half twist
  const int n = 5;
  std::vector<Triangle> f;
  auto top = [&](int i) { return Index(i % n); };
  auto bot = [&](int i) { return Index(n + i % n); };
  for (int i = 0; i < n; ++i) {
    const bool last = i == n - 1;
    const Index a = top(i), b = bot(i);
    const Index c = last ? top(0) : bot(i + 1), d = last ? bot(0) : top(i + 1);
    // last quad swaps top and bottom: the twist
    f.push_back({a, b, c});
    f.push_back({a, c, d});
  }
  Positions p = Positions::Random(2 * n, 3);
  EXPECT_THROW(IntrinsicTriangulation::from_positions(f, p), NonManifoldInput);
}

TEST(Triangulation, RejectsBadInput) {
  const TriangleMesh m = tetrahedron();
  Positions p = m.positions;
  p(2, 1) = std::nan("");
  EXPECT_THROW(IntrinsicTriangulation::from_positions(m.faces, p), InvalidInput);
  std::vector<Triangle> bad = m.faces;
  bad[1][2] = 9;
  EXPECT_THROW(IntrinsicTriangulation::from_positions(bad, m.positions), InvalidInput);
  Eigen::MatrixX3d l = Eigen::MatrixX3d::Ones(4, 3);
  l(3, 1) = -1;
  EXPECT_THROW(IntrinsicTriangulation::from_side_lengths(m.faces, 4, l, nullptr), InvalidInput);
  l(3, 1) = 1.5;  // glued sides disagree
  EXPECT_THROW(IntrinsicTriangulation::from_side_lengths(m.faces, 4, l, nullptr), InvalidInput);
}

TEST(Triangulation, SelfEdgeDeltaComplexFromLengths) {
  // Two triangles on the same three vertices glued along all three sides: a sphere with three
  // vertices. Flip one edge: the result has a self-edge (a loop at one vertex).
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 2, 1}};
  Eigen::MatrixX3d l(2, 3);
  l << 1.0, 1.2, 1.1, 1.1, 1.2, 1.0;
  auto tri = IntrinsicTriangulation::from_side_lengths(f, 3, l, nullptr);
  tri.validate();
  EXPECT_EQ(tri.n_edges(), 3);
  EXPECT_NEAR(angle_defects(tri).sum(), 4 * kPi, 1e-12);
  const double area = total_area(tri);
  int flipped = 0;
  for (Index e = 0; e < 3; ++e) flipped += tri.flip_edge(e);
  EXPECT_GT(flipped, 0);
  tri.validate();
  EXPECT_NEAR(total_area(tri), area, 1e-12);
  EXPECT_NEAR(angle_defects(tri).sum(), 4 * kPi, 1e-12);
  tri.flip_to_delaunay();
  tri.validate();
}

TEST(Triangulation, MollifyRestoresTriangleInequality) {
  // a degenerate (collinear) triangle next to a good one
  Positions p(4, 3);
  p << 0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0;
  const std::vector<Triangle> f = {{0, 1, 2}, {0, 2, 3}};
  auto tri = IntrinsicTriangulation::from_positions(f, p);
  const MollifyReport rep = tri.mollify();
  EXPECT_EQ(rep.faces_below_margin, 1);
  EXPECT_GT(rep.delta, 0.0);
  EXPECT_NEAR(rep.delta, rep.epsilon, 1e-15);  // the collinear face needed exactly ε
  for (Index fi = 0; fi < tri.n_faces(); ++fi) EXPECT_GT(face_area(tri, fi), 0.0);
  // a healthy mesh is left alone
  auto ico = IntrinsicTriangulation::from_positions(icosphere(2).faces, icosphere(2).positions);
  const auto before = ico.lengths();
  EXPECT_EQ(ico.mollify().delta, 0.0);
  EXPECT_EQ(ico.lengths(), before);
}

TEST(Triangulation, RejectsNonFiniteLengths) {
  const TriangleMesh s = jittered(icosphere(3), 0.1);
  const auto tri = IntrinsicTriangulation::from_positions(s.faces, s.positions);
  std::vector<double> hl(tri.n_halfedges());
  for (Index h = 0; h < tri.n_halfedges(); ++h) hl[h] = tri.halfedge_length(h);
  for (Index h = 0; h < tri.n_halfedges(); h += 11) {
    hl[h] = std::nan("");
    if (tri.twin(h) != kInvalidIndex) hl[tri.twin(h)] = std::nan("");
  }
  EXPECT_THROW(IntrinsicTriangulation::from_gluing(tri.tails(), tri.twins(), hl, tri.n_vertices()),
               InvalidInput);
}

TEST(Triangulation, OverflowingGeometryNeverLoops) {
  // lengths near 1e300 are finite, but their squares overflow: every Delaunay test sees NaN or
  // inf. Flipping must still stop (CGAL issue 5010 is the failure mode this guards against).
  TriangleMesh s = jittered(icosphere(4), 0.2);
  s.positions *= 1e300;
  auto tri = IntrinsicTriangulation::from_positions(s.faces, s.positions);
  const FlipReport rep = tri.flip_to_delaunay();
  EXPECT_FALSE(rep.hit_flip_cap);
  tri.validate();
}

TEST(Triangulation, FromGluingRoundTrip) {
  const TriangleMesh s = jittered(icosphere(3), 0.05);
  const auto tri = IntrinsicTriangulation::from_positions(s.faces, s.positions);
  std::vector<double> hl(tri.n_halfedges());
  for (Index h = 0; h < tri.n_halfedges(); ++h) hl[h] = tri.halfedge_length(h);
  const auto copy =
      IntrinsicTriangulation::from_gluing(tri.tails(), tri.twins(), hl, tri.n_vertices());
  copy.validate();
  EXPECT_EQ(copy.n_edges(), tri.n_edges());
  EXPECT_NEAR(total_area(copy), total_area(tri), 1e-12);
  std::vector<Index> bad_twin = tri.twins();
  std::swap(bad_twin[0], bad_twin[1]);
  EXPECT_THROW(IntrinsicTriangulation::from_gluing(tri.tails(), bad_twin, hl, tri.n_vertices()),
               InvalidInput);
}

// renumber_edges: a permutation of the edges (and of which halfedge is canonical) moves the
// lengths with them; an inconsistent listing is rejected.
TEST(Triangulation, RenumberEdgesFollowsTheListing) {
  const TriangleMesh m = jittered(grid(3, 3), 0.05, 4);  // has boundary edges
  IntrinsicTriangulation t = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const IntrinsicTriangulation original = t;
  const Index ne = t.n_edges();
  std::vector<Index> eh(ne);
  for (Index e = 0; e < ne; ++e) {
    const Index h = original.edge_halfedge(ne - 1 - e);  // reversed order
    eh[e] = original.twin(h) != kInvalidIndex && e % 2 ? original.twin(h) : h;
  }
  t.renumber_edges(eh);
  t.validate();
  for (Index e = 0; e < ne; ++e) {
    EXPECT_EQ(t.edge_halfedge(e), eh[e]);
    EXPECT_EQ(t.length(e), original.length(ne - 1 - e));
  }
  for (Index h = 0; h < t.n_halfedges(); ++h) {
    EXPECT_EQ(t.halfedge_length(h), original.halfedge_length(h));
  }
  std::vector<Index> twice = eh;
  twice[1] = twice[0];
  EXPECT_THROW(t.renumber_edges(twice), InvalidInput);
  EXPECT_THROW(t.renumber_edges(std::vector<Index>(ne - 1, 0)), InvalidInput);
}

// Save / load keeps edge ids and canonical halfedges (after refinement and flips they are no
// longer in halfedge order, which is what the loader would otherwise produce).
TEST(Triangulation, SignpostSaveLoadKeepsEdgeIds) {
  const TriangleMesh m = uv_sphere(6, 40);
  SignpostTriangulation st(m.faces, m.positions);
  delaunay_refine(st);
  const std::string path =
      (std::filesystem::temp_directory_path() / "ifem_edge_ids_test.ifem").string();
  st.save(path);
  const SignpostTriangulation back = SignpostTriangulation::load(path);
  std::filesystem::remove(path);
  const IntrinsicTriangulation& a = st.intrinsic();
  const IntrinsicTriangulation& b = back.intrinsic();
  ASSERT_EQ(a.n_edges(), b.n_edges());
  Index moved = 0;  // edges a halfedge-order numbering would have renumbered
  for (Index e = 0; e < a.n_edges(); ++e) {
    EXPECT_EQ(b.edge_halfedge(e), a.edge_halfedge(e));
    EXPECT_EQ(b.length(e), a.length(e));
    const Index h = a.edge_halfedge(e);
    if (e > 0 && h < a.edge_halfedge(e - 1)) ++moved;
  }
  for (Index h = 0; h < a.n_halfedges(); ++h) ASSERT_EQ(b.edge(h), a.edge(h));
  EXPECT_GT(moved, 0) << "the test needs a numbering that is not in halfedge order";
}

TEST(Triangulation, CanSplitEdgeAnswersBeforeSplitEdgeWouldRefuse) {
  // one face (a, b, a) whose sides a→b and b→a are glued: the edge has both sides in one face
  const IntrinsicTriangulation tri =
      IntrinsicTriangulation::from_gluing({0, 1, 0}, {1, 0, kInvalidIndex}, {1.0, 1.0, 1.0}, 2);
  const Index self_glued = tri.edge(0);
  const Index boundary = tri.edge(2);
  EXPECT_FALSE(tri.can_split_edge(self_glued));
  EXPECT_TRUE(tri.can_split_edge(boundary));
  IntrinsicTriangulation copy = tri;
  EXPECT_THROW(copy.split_edge(self_glued, 0.5), InvalidInput);
}

}  // namespace
}  // namespace ifem::intrinsic

namespace ifem::intrinsic {
namespace {

// The length scale: the plain mean when nothing stands out; lengths beyond kOutlierClip × the
// 99th percentile leave the mean whatever their size (a clipped mean would still add
// kOutlierClip × p99 for each).
TEST(Triangulation, RobustMeanLengthLeavesOutliersOut) {
  std::vector<double> l(1000);
  for (std::size_t i = 0; i < l.size(); ++i) l[i] = 1.0 + 0.001 * double(i % 7);
  const double plain = std::accumulate(l.begin(), l.end(), 0.0) / double(l.size());
  EXPECT_NEAR(robust_mean_length(l), plain, 1e-14);
  for (const double far : {10.0, 1e4, 1e300}) {
    std::vector<double> spiked = l;
    for (int k = 0; k < 6; ++k) spiked[std::size_t(k) * 100] = far;  // 0.6% of the lengths
    double kept = 0.0;
    for (std::size_t i = 0; i < l.size(); ++i) kept += i % 100 == 0 && i < 600 ? 0.0 : l[i];
    EXPECT_NEAR(robust_mean_length(spiked), kept / 994.0, 1e-14) << far;
  }
  EXPECT_EQ(robust_mean_length({}), 0.0);
  EXPECT_EQ(robust_mean_length({2.5}), 2.5);
}

// The sliver knot: closed, genus 1, oriented (positive volume), sides along the knot several
// times those around it.
TEST(Triangulation, TorusKnotTubeIsAClosedSliverTorus) {
  const TriangleMesh m = torus_knot_tube(100, 8, 0.1);
  EXPECT_EQ(m.positions.rows(), 800);
  EXPECT_EQ(m.faces.size(), 1600u);
  const auto tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  tri.validate();
  EXPECT_FALSE(tri.has_boundary());
  EXPECT_EQ(euler_characteristic(tri), 0);
  double volume = 0.0, longest = 0.0, shortest = 1e300;
  for (const Triangle& t : m.faces) {
    const Eigen::Vector3d a = m.positions.row(t[0]), b = m.positions.row(t[1]),
                          c = m.positions.row(t[2]);
    volume += a.dot(b.cross(c)) / 6.0;
    longest = std::max(longest, (b - a).norm());
    shortest = std::min(shortest, (b - a).norm());
  }
  const double tube = 0.01 * kPi;  // π r² per unit length; the knot is ~30 long
  EXPECT_GT(volume, 0.5 * tube * 25.0);
  EXPECT_LT(volume, tube * 40.0);
  EXPECT_GT(longest / shortest, 3.0);
  EXPECT_THROW(torus_knot_tube(100, 8, 0.1, 2, 4), InvalidInput);
  EXPECT_THROW(torus_knot_tube(2, 8), InvalidInput);
}

// opposite_angle_args() hands out exactly what opposite_angle() gives atan2 (FlipOut's flip
// test reads the sign of sin(α1 + α2) from them, D-147): the same bits on ordinary triangles,
// needles, caps and at extreme scales, and the cross term y1·x2 + x1·y2 has the sign of
// sin(α1 + α2) for pairs of angles summing to π ± 1e-7 .. π ± 1e-2.
TEST(Triangulation, OppositeAngleArgsAreTheAtan2Arguments) {
  // the triangle with an angle `alpha` between sides b and c: a from the law of cosines
  const auto side_a = [](double alpha, double b, double c) {
    return std::sqrt(std::max(0.0, b * b + c * c - 2.0 * b * c * std::cos(alpha)));
  };
  int checked = 0;
  for (const double scale : {1.0, 0x1p-300, 0x1p300}) {
    for (const double alpha : {1e-9, 1e-3, 0.5, 1.5707963267948966, 2.5, 3.14159}) {
      for (const double ratio : {1.0, 3.0, 1e6}) {
        const double b = scale, c = scale * ratio, a = scale * side_a(alpha, 1.0, ratio);
        double y = -1.0, x = 0.0;
        opposite_angle_args(a, b, c, &y, &x);
        EXPECT_GE(y, 0.0);
        const double direct = opposite_angle(a, b, c), via = std::atan2(y, x);
        EXPECT_EQ(std::memcmp(&direct, &via, sizeof direct), 0) << alpha << " " << ratio;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 54);
  for (const double d : {1e-7, 1e-4, 1e-2}) {
    for (const double sign : {-1.0, 1.0}) {
      const double a1 = 1.2, a2 = kPi - 1.2 + sign * d;  // sum π + sign·d
      double y1 = 0.0, x1 = 0.0, y2 = 0.0, x2 = 0.0;
      opposite_angle_args(side_a(a1, 1.0, 0.7), 1.0, 0.7, &y1, &x1);
      opposite_angle_args(side_a(a2, 0.9, 1.3), 0.9, 1.3, &y2, &x2);
      const double cross = y1 * x2 + x1 * y2;  // ∝ sin(α1 + α2): negative above π
      const bool below_zero = cross < 0.0;
      EXPECT_EQ(below_zero, sign > 0.0) << d;
    }
  }
}

}  // namespace
}  // namespace ifem::intrinsic
