// validate() of the intrinsic library's options (docs/decisions.md, "Every options struct has
// validate()"): defaults pass, every out-of-range field throws InvalidInput naming the field,
// and the functions taking the options reject them before doing any work.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/core/geometry.h"
#include "intrinsic/core/surface_point.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/refine/delaunay_refine.h"
#include "intrinsic/refine/signpost.h"
#include "intrinsic/surface/face_analysis.h"
#include "intrinsic/surface/tufted_cover.h"

namespace ifem::intrinsic {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

using test::expect_each_rejected;

TEST(OptionsValidate, RefineOptions) {
  RefineOptions{}.validate();
  expect_each_rejected(&RefineOptions::min_angle_degrees, {0.0, -1.0, 30.5, kNan},
                       "min_angle_degrees");
  RefineOptions ok;
  ok.min_angle_degrees = 30.0;
  ok.max_area = 0.5;
  ok.max_insertions = -1;
  ok.validate();
  expect_each_rejected(&RefineOptions::max_area, {-1e-9, kNan, kInf}, "max_area");
  expect_each_rejected(&RefineOptions::max_insertions, {-2}, "max_insertions");
}

TEST(OptionsValidate, RelaxOptions) {
  RelaxOptions{}.validate();
  expect_each_rejected(&RelaxOptions::iterations, {-1}, "iterations");
  expect_each_rejected(&RelaxOptions::max_edge_length, {-1.0, kNan, kInf}, "max_edge_length");
  expect_each_rejected(&RelaxOptions::max_splits, {-2}, "max_splits");
}

TEST(OptionsValidate, TraceOptions) {
  TraceOptions{}.validate();
  expect_each_rejected(&TraceOptions::start_corner, {-2, 3}, "start_corner");
  expect_each_rejected(&TraceOptions::max_steps, {-2}, "max_steps");
}

TEST(OptionsValidate, CheckedAtTheEntry) {
  const TriangleMesh m = icosphere(2);
  IntrinsicTriangulation tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  const Index faces = tri.n_faces();
  RefineOptions bad;
  bad.min_angle_degrees = 45.0;
  EXPECT_THROW(delaunay_refine(tri, bad), InvalidInput);
  EXPECT_EQ(tri.n_faces(), faces);  // nothing done
  SignpostTriangulation st(m.faces, m.positions);
  EXPECT_THROW(delaunay_refine(st, bad), InvalidInput);
  RelaxOptions bad_relax;
  bad_relax.iterations = -1;
  EXPECT_THROW(relax_inserted_vertices(st, bad_relax), InvalidInput);
  SurfacePoint start;
  start.face = 0;
  start.bary = Eigen::Vector3d(1.0 / 3, 1.0 / 3, 1.0 / 3);
  TraceOptions bad_trace;
  bad_trace.start_corner = 5;
  EXPECT_THROW(trace_straight(tri, start, Eigen::Vector2d(1, 0), 0.1, bad_trace), InvalidInput);
}

// The options form of trace_straight() is the positional one with names.
TEST(OptionsValidate, TraceOptionsMatchPositional) {
  const TriangleMesh m = grid(6, 6);
  const IntrinsicTriangulation tri = IntrinsicTriangulation::from_positions(m.faces, m.positions);
  SurfacePoint start;
  start.face = 7;
  start.bary = Eigen::Vector3d(0.2, 0.3, 0.5);
  const Eigen::Vector2d dir(std::cos(0.3), std::sin(0.3));
  TraceOptions o;
  o.record_path = true;
  o.slide_on_boundary = true;
  const TraceResult a = trace_straight(tri, start, dir, 0.4, o);
  const TraceResult b =
      trace_straight(tri, start, dir, 0.4, -1, true, true, 4 * tri.n_faces() + 1000);
  EXPECT_EQ(a.end.face, b.end.face);
  EXPECT_EQ(a.end.bary, b.end.bary);
  EXPECT_EQ(a.path.size(), b.path.size());
  EXPECT_GT(a.path.size(), 1u);
}

// The argument orders of tufted_cover(): report last; the old order still works.
TEST(OptionsValidate, TuftedCoverArgumentOrders) {
  const TriangleMesh m = tetrahedron();
  TuftedCoverReport r_new, r_old;
  const IntrinsicTriangulation a = tufted_cover(m.faces, m.positions, 3, &r_new);
  const IntrinsicTriangulation b = tufted_cover(m.faces, m.positions, &r_old, 3);
  EXPECT_EQ(a.multiplicity(), 6);
  EXPECT_EQ(b.multiplicity(), 6);
  EXPECT_EQ(a.lengths(), b.lengths());
  EXPECT_EQ(r_new.edges, r_old.edges);
  EXPECT_EQ(tufted_cover(m.faces, m.positions).multiplicity(), 2);
  EXPECT_THROW(tufted_cover(m.faces, m.positions, 0), InvalidInput);
}

// One SurfacePoint type whose default is "no face"; the two mean lengths differ as documented.
TEST(OptionsValidate, SurfacePointAndMeanLengths) {
  const SurfacePoint p;
  EXPECT_EQ(p.face, kInvalidIndex);
  // A single triangle with sides 3, 4, 5: each side once either way.
  Positions x(3, 3);
  x << 0, 0, 0, 3, 0, 0, 0, 4, 0;
  const std::vector<Triangle> one = {{0, 1, 2}};
  EXPECT_DOUBLE_EQ(mean_side_length(one, x), 4.0);
  EXPECT_DOUBLE_EQ(mean_edge_length(IntrinsicTriangulation::from_positions(one, x)), 4.0);
  // Two triangles sharing the long side: the shared side counts twice as a side, once as an edge.
  Positions y(4, 3);
  y << 0, 0, 0, 3, 0, 0, 0, 4, 0, 3, 4, 0;
  const std::vector<Triangle> two = {{0, 1, 2}, {1, 3, 2}};
  EXPECT_DOUBLE_EQ(mean_side_length(two, y), (3 + 4 + 5 + 4 + 3 + 5) / 6.0);
  EXPECT_DOUBLE_EQ(mean_edge_length(IntrinsicTriangulation::from_positions(two, y)),
                   (3 + 4 + 5 + 4 + 3) / 5.0);
}

}  // namespace
}  // namespace ifem::intrinsic
