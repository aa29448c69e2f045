#include "intrinsic/geodesic/flip_geodesic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/flip_network.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::intrinsic {
namespace {

// A flat square grid with its interior vertices jittered in x and y (the boundary stays a
// square, so the region is convex and every geodesic is a straight segment).
TriangleMesh flat_jittered_grid(int n, double amount, unsigned seed) {
  TriangleMesh m = grid(n, n);
  unsigned s = seed;
  auto rnd = [&]() {
    s = s * 1664525u + 1013904223u;
    return (s >> 8) / double(1u << 24) - 0.5;
  };
  for (Eigen::Index i = 0; i < m.positions.rows(); ++i) {
    const double x = m.positions(i, 0), y = m.positions(i, 1);
    const bool boundary = x < 1e-12 || y < 1e-12 || x > 1 - 1e-12 || y > 1 - 1e-12;
    const double dx = amount * rnd() / n, dy = amount * rnd() / n;
    if (!boundary) {
      m.positions(i, 0) += dx;
      m.positions(i, 1) += dy;
    }
  }
  return m;
}

using test::polyline_length;

// Shortens step by step (one reroute per call) and checks the length never increases.
FlipOutReport shorten_monotone(SignpostTriangulation& st, EdgePath& path,
                               const FlipOutOptions& opt) {
  FlipOutReport total;
  total.initial_length = path_length(st.intrinsic(), path);
  double last = total.initial_length;
  FlipOutOptions one = opt;
  one.max_iterations = 1;
  for (int k = 0; k < 100000; ++k) {
    const FlipOutReport r = shorten(st, path, one);
    total.flips += r.flips;
    total.iterations += r.iterations;
    EXPECT_LE(r.final_length, last * (1 + 1e-15));
    last = r.final_length;
    total.stopped_by = r.stopped_by;
    if (r.stopped_by != FlipOutStop::kIterationCap) break;
  }
  total.final_length = last;
  return total;
}

TEST(FlipGeodesic, FlatGridPathsAreStraightSegments) {
  const TriangleMesh m = flat_jittered_grid(12, 0.6, 7);
  std::vector<std::pair<Index, Index>> pairs = {{14, 154}, {15, 120}, {27, 100}, {0, 168},
                                                {12, 156}, {40, 130}, {3, 165}};
  unsigned r = 11;  // plus pseudo-random pairs, boundary vertices included
  for (int k = 0; k < 40; ++k) {
    r = r * 1664525u + 1013904223u;
    const Index a = static_cast<Index>((r >> 8) % 169);
    r = r * 1664525u + 1013904223u;
    const Index b = static_cast<Index>((r >> 8) % 169);
    if (a != b) pairs.push_back({a, b});
  }
  for (const auto& [a, b] : pairs) {
    SignpostTriangulation st(m.faces, m.positions);
    const double area0 = total_area(st.intrinsic());
    EdgePath path = shortest_edge_path(st, a, b);
    const double dijkstra = path_length(st.intrinsic(), path);
    const FlipOutOptions opt;
    const FlipOutReport rep = shorten_monotone(st, path, opt);
    const double euclid = (m.positions.row(a) - m.positions.row(b)).norm();
    EXPECT_EQ(rep.stopped_by, FlipOutStop::kConverged) << a << "-" << b;
    EXPECT_NEAR(rep.final_length, euclid, 1e-9 * euclid) << a << "-" << b;
    EXPECT_LE(rep.final_length, dijkstra * (1 + 1e-15));
    EXPECT_NEAR(path_length(st.intrinsic(), path), rep.final_length, 1e-12 * euclid);
    EXPECT_GE(min_wedge_angle(st.intrinsic(), path), kPi - opt.angle_epsilon);
    EXPECT_NO_THROW(st.intrinsic().validate());
    EXPECT_NEAR(total_area(st.intrinsic()), area0, 1e-9 * area0);
    ASSERT_FALSE(path.steps.empty());
    EXPECT_EQ(step_tail(st.intrinsic(), path.steps.front()), a);
    EXPECT_EQ(step_head(st.intrinsic(), path.steps.back()), b);
    const std::vector<Eigen::Vector3d> line = path_polyline(st, path);
    EXPECT_NEAR(polyline_length(line), rep.final_length, 1e-6 * rep.final_length);
    EXPECT_LT((line.front() - m.positions.row(a).transpose()).norm(), 1e-9);
    EXPECT_LT((line.back() - m.positions.row(b).transpose()).norm(), 1e-9);
  }
}

TEST(FlipGeodesic, IcospherePathBetweenChordAndDijkstra) {
  const TriangleMesh m = icosphere(6);
  SignpostTriangulation st(m.faces, m.positions);
  const Index a = 0;
  Index b = 1;  // the vertex farthest from a, but not antipodal (a unique geodesic)
  double best = -1.0;
  for (Index v = 1; v < m.positions.rows(); ++v) {
    const double d = (m.positions.row(v) - m.positions.row(a)).norm();
    if (d < 1.6 && d > best) best = d, b = v;
  }
  EdgePath path = shortest_edge_path(st, a, b);
  const double dijkstra = path_length(st.intrinsic(), path);
  const FlipOutReport rep = shorten(st, path);
  const double chord = (m.positions.row(a) - m.positions.row(b)).norm();
  const double arc = 2.0 * std::asin(chord / 2.0);
  EXPECT_EQ(rep.stopped_by, FlipOutStop::kConverged);
  EXPECT_GT(rep.flips, 0);
  EXPECT_GE(rep.final_length, chord);
  EXPECT_LT(rep.final_length, dijkstra);
  // an inscribed polyhedron is shorter than the sphere, but not by much at this resolution
  EXPECT_LE(rep.final_length, arc);
  EXPECT_GE(rep.final_length, 0.98 * arc);
  EXPECT_GE(min_wedge_angle(st.intrinsic(), path), kPi - FlipOutOptions{}.angle_epsilon);
  EXPECT_NO_THROW(st.intrinsic().validate());
  const std::vector<Eigen::Vector3d> line = path_polyline(st, path);
  EXPECT_NEAR(polyline_length(line), rep.final_length, 1e-6 * rep.final_length);
}

// After a flip FlipOut splices its wedge in place where the two flipped faces have one corner at
// the joint (docs/decisions.md D-385): the spliced wedge must be the one walked again. On an
// icosphere, and on a Δ-complex: an icosphere with one vertex pulled out into a spike (angle sum
// below π), whose edges are flipped away until none flips (faces with two corners at one vertex
// appear around it, and there the wedge is walked instead; the test makes sure both ways occur).
TEST(FlipGeodesic, SplicedWedgesEqualWalkedOnes) {
  for (const bool spike : {false, true}) {
    TriangleMesh m = icosphere(4);
    const Index v = 0;
    if (spike) m.positions.row(v) *= 4.0;
    SignpostTriangulation st(m.faces, m.positions);
    const IntrinsicTriangulation& tri = st.intrinsic();
    for (int round = 0; spike && round < 50; ++round) {
      bool any = false;
      for (Index h = 0; h < tri.n_halfedges(); ++h) {
        if (tri.tail(h) == v && tri.twin(h) != kInvalidIndex)
          any = st.flip_edge(tri.edge(h)) || any;
      }
      if (!any) break;
    }
    Index x = v;  // a vertex with two corners in one face, if any
    for (Index f = 0; f < tri.n_faces(); ++f) {
      const Index a = tri.tail(3 * f), b = tri.tail(3 * f + 1), c = tri.tail(3 * f + 2);
      if (a == b || b == c || a == c) x = a == b || a == c ? a : b;
    }
    std::vector<Index> ends;  // vertices near x (every 7th vertex without a spike)
    for (Index u = 0; u < m.positions.rows(); ++u) {
      const double d = (m.positions.row(u) - m.positions.row(x)).norm();
      if (spike ? u != v && d < 0.9 : u % 7 == 0) ends.push_back(u);
    }
    Index spliced = 0, walked = 0;
    for (const Index a : ends) {
      for (const Index b : ends) {
        if (b <= a) continue;
        EdgePath path = shortest_edge_path(st, a, b);
        std::vector<int> uses;
        detail::FlipNetwork net(st, uses, nullptr);
        net.check_splices = true;
        net.add(path, 0);
        FlipOutReport rep;
        ASSERT_NO_THROW(net.run(FlipOutOptions{}, rep))
            << "spike " << spike << ", " << a << "-" << b;
        EXPECT_LE(rep.final_length, rep.initial_length);
        spliced += net.spliced_flips;
        walked += net.walked_flips;
      }
    }
    EXPECT_GT(spliced, 100) << "spike " << spike;  // 7,451 and 1,089 when written (3 walked)
    if (spike) {
      EXPECT_GT(walked, 0);
    }
    EXPECT_NO_THROW(tri.validate());
  }
}

// On a refined intrinsic triangulation (inserted vertices, Delaunay flips), a path between two
// inserted vertices of a flat region is still the straight segment, and traces onto the input.
TEST(FlipGeodesic, RefinedFlatTriangulationWithInsertedEndpoints) {
  const TriangleMesh m = flat_jittered_grid(6, 0.6, 3);
  SignpostTriangulation st(m.faces, m.positions);
  st.flip_to_delaunay();
  const Index a = st.insert_vertex(7, Eigen::Vector3d(0.2, 0.3, 0.5));
  const Index b = st.insert_vertex(50, Eigen::Vector3d(0.6, 0.3, 0.1));
  delaunay_refine(st);
  EdgePath path = shortest_edge_path(st, a, b);
  const FlipOutReport rep = shorten(st, path);
  const Positions x = st.vertex_positions();
  const double euclid = (x.row(a) - x.row(b)).norm();
  EXPECT_EQ(rep.stopped_by, FlipOutStop::kConverged);
  EXPECT_NEAR(rep.final_length, euclid, 1e-9 * euclid);
  EXPECT_NO_THROW(st.intrinsic().validate());
  const std::vector<Eigen::Vector3d> line = path_polyline(st, path);
  EXPECT_NEAR(polyline_length(line), rep.final_length, 1e-6 * rep.final_length);
}

// The iteration cap stops early (and is reported); a path with a backtrack loses it.
TEST(FlipGeodesic, IterationCapAndBacktrack) {
  const TriangleMesh m = flat_jittered_grid(8, 0.6, 5);
  SignpostTriangulation st(m.faces, m.positions);
  EdgePath path = shortest_edge_path(st, 10, 70);
  FlipOutOptions opt;
  opt.max_iterations = 0;
  const FlipOutReport capped = shorten(st, path, opt);
  EXPECT_EQ(capped.stopped_by, FlipOutStop::kIterationCap);
  EXPECT_EQ(capped.iterations, 0);
  EXPECT_EQ(capped.final_length, capped.initial_length);
  // append a step and its reverse: the path must come back to the same geodesic
  const double before = shorten(st, path).final_length;
  const IntrinsicTriangulation& tri = st.intrinsic();
  const Index h = tri.vertex_halfedge(70);
  const PathStep out = {tri.edge(h), tri.edge_halfedge(tri.edge(h)) == h};
  const Index mid = static_cast<Index>(path.steps.size()) - 1;
  path.steps.insert(path.steps.begin() + mid + 1, {out, {out.edge, !out.forward}});
  const FlipOutReport rep = shorten(st, path);
  EXPECT_EQ(rep.stopped_by, FlipOutStop::kConverged);
  EXPECT_NEAR(rep.final_length, before, 1e-12 * before);
}

TEST(FlipGeodesic, UnreachableAndBadInputThrow) {
  TriangleMesh m = grid(2, 2);
  const Index nv = static_cast<Index>(m.positions.rows());
  Positions x(2 * nv, 3);
  x << m.positions, (m.positions.rowwise() + Eigen::RowVector3d(5, 0, 0));
  std::vector<Triangle> faces = m.faces;
  for (const Triangle& t : m.faces) faces.push_back({t[0] + nv, t[1] + nv, t[2] + nv});
  SignpostTriangulation st(faces, x);
  EXPECT_THROW(shortest_edge_path(st, 0, nv), InvalidInput);
  EXPECT_THROW(shortest_edge_path(st, 0, 0), InvalidInput);
  EXPECT_THROW(shortest_edge_path(st, 0, 2 * nv), InvalidInput);
  EXPECT_NO_THROW(shortest_edge_path(st, 0, nv - 1));
  FlipOutOptions bad;
  bad.angle_epsilon = -1;
  EXPECT_THROW(bad.validate(), InvalidInput);
  bad = {};
  bad.max_iterations = -2;
  EXPECT_THROW(bad.validate(), InvalidInput);
  bad = {};
  bad.min_relative_decrease = std::nan("");
  EXPECT_THROW(bad.validate(), InvalidInput);
  EdgePath broken;
  broken.steps = {{0, true}, {0, true}};
  EXPECT_THROW(shorten(st, broken), InvalidInput);
}

// An open tube around the z axis, n around and m + 1 rings, radius r(z) = 1 + 4 (z − 1/2)²: an
// hourglass whose waist ring (z = 1/2, m even) is the shortest loop around it.
TriangleMesh hourglass(int n, int m) {
  TriangleMesh t;
  t.positions.resize(n * (m + 1), 3);
  for (int j = 0; j <= m; ++j) {
    const double z = double(j) / m, r = 1.0 + 4.0 * (z - 0.5) * (z - 0.5);
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * kPi * (i + 0.5 * (j % 2)) / n;
      t.positions.row(j * n + i) << r * std::cos(a), r * std::sin(a), z;
    }
  }
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      const Index a = j * n + i, b = j * n + (i + 1) % n, c = (j + 1) * n + i,
                  d = (j + 1) * n + (i + 1) % n;
      if (j % 2 == 0) {
        t.faces.push_back({a, b, c});
        t.faces.push_back({b, d, c});
      } else {
        t.faces.push_back({a, d, c});
        t.faces.push_back({a, b, d});
      }
    }
  }
  return t;
}

// Flips keep the surface: every input vertex's total angle, summed over the current
// triangulation's corners, is still the input's (to 1e-9 radians).
void expect_angle_sums_kept(const SignpostTriangulation& st) {
  const IntrinsicTriangulation& tri = st.intrinsic();
  std::vector<double> sum(tri.n_vertices(), 0.0);
  for (Index h = 0; h < tri.n_halfedges(); ++h) sum[tri.tail(h)] += corner_angle(tri, h);
  for (Index v = 0; v < st.n_input_vertices(); ++v) {
    EXPECT_NEAR(sum[v], st.vertex_angle_sum(v), 1e-9) << "vertex " << v;
  }
}

// Every joint of a converged curve that is not pinned bends by no less than π − ε on both sides.
void expect_straight(const IntrinsicTriangulation& tri, const EdgePath& p, double eps) {
  EXPECT_GE(min_wedge_angle(tri, p), kPi - eps);
}

TEST(FlipGeodesic, LoopAroundHourglassShrinksToTheWaist) {
  const int n = 24, m = 8;
  const TriangleMesh t = hourglass(n, m);
  SignpostTriangulation st(t.faces, t.positions);
  std::vector<Index> ring;  // the top ring, as the initial loop
  for (int i = 0; i < n; i += 3) ring.push_back(m * n + i);
  EdgePath loop = edge_path_through(st.intrinsic(), ring, true, false);
  const double sum0 = total_area(st.intrinsic());
  const FlipOutReport rep = shorten(st, loop);
  const double waist = n * 2.0 * std::sin(kPi / n);  // the waist ring's polygon, r = 1
  EXPECT_EQ(rep.stopped_by, FlipOutStop::kConverged) << to_string(rep.stopped_by);
  EXPECT_TRUE(rep.collapsed_loops.empty());
  EXPECT_TRUE(loop.closed);
  EXPECT_NEAR(rep.final_length, waist, 1e-9 * waist);
  EXPECT_LT(rep.final_length, rep.initial_length);
  expect_straight(st.intrinsic(), loop, FlipOutOptions{}.angle_epsilon);
  EXPECT_NEAR(total_area(st.intrinsic()), sum0, 1e-9 * sum0);
  expect_angle_sums_kept(st);
  const std::vector<Eigen::Vector3d> line = path_polyline(st, loop);
  EXPECT_LT((line.front() - line.back()).norm(), 1e-9);
  EXPECT_NEAR(polyline_length(line), rep.final_length, 1e-6 * rep.final_length);
  for (const Eigen::Vector3d& x : line) EXPECT_NEAR(x.z(), 0.5, 1e-9);
}

// A loop around one vertex of a sphere is contractible: it shrinks until it cannot go on, and
// is reported as collapsed (never spun on), whatever the cap.
TEST(FlipGeodesic, ContractibleLoopTerminatesAndIsReported) {
  const TriangleMesh t = icosphere(4);
  for (const Index centre : {Index(0), Index(17), Index(100)}) {
    SignpostTriangulation st(t.faces, t.positions);
    std::vector<Index> ring;
    const IntrinsicTriangulation& tri = st.intrinsic();
    const Index h0 = tri.vertex_halfedge(centre);
    for (Index x = h0;;) {
      ring.push_back(tri.head(x));
      x = tri.twin(IntrinsicTriangulation::prev(x));
      if (x == h0) break;
    }
    EdgePath loop = edge_path_through(tri, ring, true, false);
    const double area = total_area(tri);
    const FlipOutReport rep = shorten(st, loop);
    EXPECT_EQ(rep.collapsed_loops, std::vector<Index>{0}) << centre;
    EXPECT_NE(rep.stopped_by, FlipOutStop::kIterationCap) << centre;
    EXPECT_LT(rep.final_length, 0.5 * rep.initial_length) << centre;
    EXPECT_NO_THROW(st.intrinsic().validate());
    EXPECT_NEAR(total_area(st.intrinsic()), area, 1e-9 * area);
    expect_angle_sums_kept(st);
  }
}

// Two curves sharing an endpoint straighten to their segments; a curve routed around the end of
// another keeps going around it (no new crossing): it wraps at that end vertex.
TEST(FlipGeodesic, NetworkStaysNoncrossing) {
  const TriangleMesh m = grid(10, 10);  // 11 × 11 vertices at multiples of 0.1
  auto id = [](int i, int j) { return Index(j * 11 + i); };
  SignpostTriangulation st(m.faces, m.positions);
  const IntrinsicTriangulation& tri = st.intrinsic();
  std::vector<EdgePath> net = {
      edge_path_through(tri, {id(3, 5), id(7, 5)}, false, false),            // A
      edge_path_through(tri, {id(5, 3), id(9, 5), id(5, 7)}, false, false),  // B, around A
      edge_path_through(tri, {id(3, 5), id(1, 9)}, false, false)};           // C, shares A's end
  const FlipOutReport rep = shorten(st, net);
  EXPECT_NEAR(rep.lengths[0], 0.4, 1e-9);
  EXPECT_NEAR(rep.lengths[1], 2.0 * std::sqrt(0.08), 1e-9);  // wraps at (0.7, 0.5)
  EXPECT_NEAR(rep.lengths[2], std::sqrt(0.2 * 0.2 + 0.4 * 0.4), 1e-9);
  const std::vector<Index> bv = path_vertices(tri, net[1]);
  EXPECT_NE(std::find(bv.begin(), bv.end(), id(7, 5)), bv.end());
  // without A, B straightens through it
  SignpostTriangulation alone(m.faces, m.positions);
  EdgePath b = edge_path_through(alone.intrinsic(), {id(5, 3), id(9, 5), id(5, 7)}, false, false);
  EXPECT_NEAR(shorten(alone, b).final_length, 0.4, 1e-9);
  const std::vector<char> flags = curve_edge_flags(tri, net);
  for (const EdgePath& p : net) {
    for (const PathStep& s : p.steps) EXPECT_EQ(flags[s.edge], 1);
  }
}

// Pinned waypoints stay on the path; the pieces between them are straight.
TEST(FlipGeodesic, PinnedWaypointsStay) {
  const TriangleMesh m = flat_jittered_grid(10, 0.5, 9);
  SignpostTriangulation st(m.faces, m.positions);
  const std::vector<Index> via = {0, 55, 9, 99};
  EdgePath p = edge_path_through(st.intrinsic(), via, false, true, JoinBy::kDirectEdges);
  ASSERT_EQ(p.pinned.size(), 2u);
  const FlipOutReport rep = shorten(st, p);
  double expect = 0.0;
  for (std::size_t i = 0; i + 1 < via.size(); ++i) {
    expect += (m.positions.row(via[i]) - m.positions.row(via[i + 1])).norm();
  }
  EXPECT_EQ(rep.stopped_by, FlipOutStop::kConverged);
  EXPECT_NEAR(rep.final_length, expect, 1e-9 * expect);
  const std::vector<Index> pv = path_vertices(st.intrinsic(), p);
  for (const Index v : via) EXPECT_NE(std::find(pv.begin(), pv.end(), v), pv.end()) << v;
  for (const Index j : p.pinned) {
    EXPECT_TRUE(pv[j] == 55 || pv[j] == 9) << pv[j];
  }
}

// Endpoints anywhere on the surface: inserted as vertices (inside a face, on an edge, at a
// vertex), traced back to the same 3D points; the path between them is the segment.
TEST(FlipGeodesic, SurfacePointEndpoints) {
  const TriangleMesh m = flat_jittered_grid(8, 0.5, 4);
  SignpostTriangulation st(m.faces, m.positions);
  auto point = [&](Index f, Eigen::Vector3d b) {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) x += b[k] * m.positions.row(m.faces[f][k]).transpose();
    return x;
  };
  const SurfacePoint in_face{20, {0.2, 0.3, 0.5}}, on_edge{75, {0.0, 0.4, 0.6}},
      at_vertex{40, {0.0, 1.0, 0.0}}, second_in_face{20, {0.6, 0.3, 0.1}};
  const Index nv = st.intrinsic().n_vertices();
  const Index a = insert_surface_point(st, in_face);
  const Index b = insert_surface_point(st, on_edge);
  const Index c = insert_surface_point(st, at_vertex);
  const Index d = insert_surface_point(st, second_in_face);  // the face is split already
  EXPECT_EQ(a, nv);
  EXPECT_EQ(b, nv + 1);
  EXPECT_EQ(c, m.faces[40][1]);
  EXPECT_EQ(d, nv + 2);
  EXPECT_EQ(insert_surface_point(st, in_face), a);  // the same point again: the same vertex
  const Positions x = st.vertex_positions();
  EXPECT_LT((x.row(a).transpose() - point(20, in_face.bary)).norm(), 1e-12);
  EXPECT_LT((x.row(b).transpose() - point(75, on_edge.bary)).norm(), 1e-12);
  EXPECT_LT((x.row(d).transpose() - point(20, second_in_face.bary)).norm(), 1e-12);
  for (const auto& [s, t] : std::vector<std::pair<Index, Index>>{{a, b}, {b, d}, {d, c}}) {
    EdgePath p = shortest_edge_path(st, s, t);
    const FlipOutReport rep = shorten(st, p);
    const double euclid = (x.row(s) - x.row(t)).norm();
    EXPECT_NEAR(rep.final_length, euclid, 1e-9 * euclid);
    const std::vector<Eigen::Vector3d> line = path_polyline(st, p);
    EXPECT_LT((line.front() - x.row(s).transpose()).norm(), 1e-9);
    EXPECT_LT((line.back() - x.row(t).transpose()).norm(), 1e-9);
  }
  EXPECT_THROW(insert_surface_point(st, {int(st.input().n_faces()), {1, 0, 0}}), InvalidInput);
  EXPECT_THROW(insert_surface_point(st, {0, {0.5, 0.6, 0.1}}), InvalidInput);
  EXPECT_THROW(insert_surface_point(st, {0, {-0.5, 1.0, 0.5}}), InvalidInput);
}

// Collinear control points on a flat mesh: the Bézier curve is the segment between the ends,
// whatever the degree and the rounds.
TEST(FlipGeodesic, BezierWithCollinearControlsIsTheSegment) {
  const TriangleMesh m = grid(12, 12);  // 13 × 13 vertices
  auto id = [](int i, int j) { return Index(j * 13 + i); };
  for (const int rounds : {0, 1, 3}) {
    for (const std::vector<Index>& ctrl : std::vector<std::vector<Index>>{
             {id(1, 1), id(4, 4), id(8, 8), id(11, 11)}, {id(0, 6), id(6, 6), id(12, 6)}}) {
      SignpostTriangulation st(m.faces, m.positions);
      const BezierCurve c = bezier_curve(st, ctrl, rounds);
      const double seg = (m.positions.row(ctrl.front()) - m.positions.row(ctrl.back())).norm();
      EXPECT_NEAR(c.report.final_length, seg, 1e-9 * seg) << rounds;
      EXPECT_EQ(c.controls.front(), ctrl.front());
      EXPECT_EQ(c.controls.back(), ctrl.back());
      const std::vector<Eigen::Vector3d> line = path_polyline(st, c.path);
      EXPECT_NEAR(polyline_length(line), seg, 1e-9 * seg);
    }
  }
}

// A curved control polygon: more rounds, more control points; the curve stays between the
// chord and the control polygon in length, and a quadratic curve on the plane matches the
// exact Bézier curve's length.
TEST(FlipGeodesic, BezierQuadraticOnThePlane) {
  const TriangleMesh m = flat_jittered_grid(25, 0.4, 2);  // 26 × 26 vertices
  const Index a = 2 * 26 + 2, b = 22 * 26 + 12, c = 2 * 26 + 22;
  SignpostTriangulation st(m.faces, m.positions);
  const BezierCurve curve = bezier_curve(st, {a, b, c}, 4);
  EXPECT_EQ(curve.controls.size(), 2u * 16 + 1);
  const Eigen::Vector2d p0 = m.positions.row(a).head<2>(), p1 = m.positions.row(b).head<2>(),
                        p2 = m.positions.row(c).head<2>();
  double exact = 0.0;  // arc length of the planar quadratic Bézier, by fine sampling
  Eigen::Vector2d last = p0;
  for (int k = 1; k <= 20000; ++k) {
    const double t = k / 20000.0;
    const Eigen::Vector2d q = (1 - t) * (1 - t) * p0 + 2 * t * (1 - t) * p1 + t * t * p2;
    exact += (q - last).norm();
    last = q;
  }
  EXPECT_NEAR(curve.report.final_length, exact, 2e-3 * exact);
  EXPECT_GT(curve.inserted_vertices, 0);
  EXPECT_NO_THROW(st.intrinsic().validate());
  EXPECT_THROW(bezier_curve(st, {a}, 2), InvalidInput);
  EXPECT_THROW(bezier_curve(st, {a, a, b}, 2), InvalidInput);
  EXPECT_THROW(bezier_curve(st, {a, b}, -1), InvalidInput);
}

// Single-source geodesics on a flat convex mesh are the straight segments from the source;
// the triangulation holds every one of them as an edge path.
TEST(FlipGeodesic, SingleSourceOnFlatMeshIsEuclidean) {
  const TriangleMesh m = flat_jittered_grid(14, 0.6, 12);
  for (const Index src : {Index(0), Index(7 * 15 + 6), Index(15 * 5 - 1)}) {
    SignpostTriangulation st(m.faces, m.positions);
    const double area = total_area(st.intrinsic());
    const SingleSourceGeodesics g = single_source_geodesics(st, src);
    EXPECT_EQ(g.blocked, 0);
    for (Index v = 0; v < m.positions.rows(); ++v) {
      const double euclid = (m.positions.row(v) - m.positions.row(src)).norm();
      ASSERT_NEAR(g.length[v], euclid, 1e-9 * std::max(euclid, 1.0)) << src << " → " << v;
      const EdgePath& p = g.paths[v];
      EXPECT_NEAR(path_length(st.intrinsic(), p), g.length[v], 1e-12);
      if (v == src) continue;
      ASSERT_FALSE(p.steps.empty());
      EXPECT_EQ(step_tail(st.intrinsic(), p.steps.front()), src);
      EXPECT_EQ(step_head(st.intrinsic(), p.steps.back()), v);
      for (const PathStep& s : p.steps) EXPECT_EQ(g.tree_edges[s.edge], 1);
    }
    EXPECT_NO_THROW(st.intrinsic().validate());
    EXPECT_NEAR(total_area(st.intrinsic()), area, 1e-9 * area);
    expect_angle_sums_kept(st);
  }
}

// On a closed curved surface every length is a geodesic's: at least the chord, and on a sphere
// at least the distance along the inscribed polyhedron's shortest path (FlipOut's own two-point
// path is a geodesic too, so single-source cannot beat it by more than round-off); a second
// component stays unreachable.
TEST(FlipGeodesic, SingleSourceOnASphere) {
  const TriangleMesh t = icosphere(6);
  SignpostTriangulation st(t.faces, t.positions);
  const SingleSourceGeodesics g = single_source_geodesics(st, 0);
  int equal = 0, checked = 0;
  for (Index v = 1; v < t.positions.rows(); v += 7) {
    const double chord = (t.positions.row(v) - t.positions.row(0)).norm();
    EXPECT_GE(g.length[v], chord * (1 - 1e-12));
    EXPECT_LE(g.length[v], 2.0 * std::asin(std::min(1.0, chord / 2.0)) * (1 + 1e-12));
    SignpostTriangulation other(t.faces, t.positions);
    EdgePath p = shortest_edge_path(other, 0, v);
    const double two_point = shorten(other, p).final_length;
    ++checked;
    if (std::abs(two_point - g.length[v]) <= 1e-9 * two_point) ++equal;
    EXPECT_LE(g.length[v], two_point * (1 + 1e-9)) << v;  // never a longer geodesic here
  }
  std::printf(
      "single-source vs two-point FlipOut on icosphere(6): %d of %d equal (the others "
      "shorter), %d blocked\n",
      equal, checked, int(g.blocked));
  EXPECT_EQ(g.blocked, 0);
  EXPECT_THROW(single_source_geodesics(st, -1), InvalidInput);
}

// Single-source geodesics judge most joints from the signposts at their vertex and hand a
// path's joints on to the paths that extend it, without summing wedges again; spot's run
// makes vertices of high valence (wedges of hundreds of faces) and blocked paths. Every
// joint is checked here by summing its wedges face by face: a path whose run converged is
// straight everywhere, so only blocked runs may leave a bent joint, and the reported lengths
// are those of the paths.
TEST(FlipGeodesic, SingleSourceJointsAgreeWithWedgeSums) {
  const io::SurfaceInput in = io::read_mesh((test::test_data() / "spot.obj").string());
  const double limit = kPi - FlipOutOptions{}.angle_epsilon;
  for (const Index src : {0, 1234}) {
    SignpostTriangulation st(in.triangles, in.positions);
    const SingleSourceGeodesics g = single_source_geodesics(st, src);
    const IntrinsicTriangulation& tri = st.intrinsic();
    Index bent = 0;
    for (Index v = 0; v < tri.n_vertices(); ++v) {
      const EdgePath& p = g.paths[v];
      ASSERT_NEAR(path_length(tri, p), g.length[v], 1e-12 * std::max(1.0, g.length[v])) << v;
      if (min_wedge_angle(tri, p) < limit) ++bent;
    }
    std::vector<Index> valence(tri.n_vertices(), 0);
    for (Index h = 0; h < tri.n_halfedges(); ++h) ++valence[tri.tail(h)];
    const Index max_valence = *std::max_element(valence.begin(), valence.end());
    EXPECT_LE(bent, g.blocked) << "source " << src;
    EXPECT_GT(max_valence, 64) << "no hub: the long-wedge branch is not exercised";
  }
}

// Two tetrahedra sharing one vertex (edge-manifold, pinched there): single-source geodesics
// cross the pinch, as the two-point search does; in a tetrahedron every vertex is adjacent, so
// a far vertex's length is the two edges through the shared vertex.
TEST(FlipGeodesic, SingleSourceCrossesAPinchedVertex) {
  const TriangleMesh t = tetrahedron();
  const Index n = static_cast<Index>(t.positions.rows());
  Positions x(2 * n - 1, 3);
  x.topRows(n) = t.positions;
  auto twin_id = [n](Index i) { return i == 0 ? Index(0) : n + i - 1; };
  for (Index i = 1; i < n; ++i) x.row(twin_id(i)) = 2 * t.positions.row(0) - t.positions.row(i);
  std::vector<Triangle> faces = t.faces;
  for (const Triangle& f : t.faces) faces.push_back({twin_id(f[0]), twin_id(f[2]), twin_id(f[1])});
  SignpostTriangulation st(faces, x, 0.0);
  const SingleSourceGeodesics g = single_source_geodesics(st, 1);
  const double to_pinch = (x.row(1) - x.row(0)).norm();
  for (Index i = 1; i < n; ++i) {
    const double expect = to_pinch + (x.row(twin_id(i)) - x.row(0)).norm();
    EXPECT_NEAR(g.length[twin_id(i)], expect, 1e-12 * expect) << twin_id(i);
  }
}

TEST(FlipGeodesic, PathThroughChecksItsVertices) {
  const TriangleMesh m = grid(3, 3);  // 16 vertices
  SignpostTriangulation st(m.faces, m.positions);
  const IntrinsicTriangulation& tri = st.intrinsic();
  EXPECT_THROW(edge_path_through(tri, {0, 5, 5, 9}, false, true), InvalidInput);
  EXPECT_THROW(edge_path_through(tri, {0, 5, 0}, true, false), InvalidInput);
  EXPECT_THROW(edge_path_through(tri, {0, 16}, false, false), InvalidInput);
  EXPECT_THROW(edge_path_through(tri, {3}, false, false), InvalidInput);
  const EdgePath p = edge_path_through(tri, {0, 1, 2, 3}, false, false, JoinBy::kDirectEdges);
  EXPECT_EQ(p.steps.size(), 3u);
  const std::vector<Index> pv = path_vertices(tri, p);
  EXPECT_EQ(pv, (std::vector<Index>{0, 1, 2, 3}));
}

}  // namespace
}  // namespace ifem::intrinsic
