#include "intrinsic/geodesic/flip_geodesic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/generators/mesh_generators.h"
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

double polyline_length(const std::vector<Eigen::Vector3d>& line) {
  double s = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) s += (line[i] - line[i - 1]).norm();
  return s;
}

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

}  // namespace
}  // namespace ifem::intrinsic
