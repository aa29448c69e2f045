// The trace recipe (solvers/recipes/trace_geodesic.h) against exact truths: straight lines of
// exact length and end point on a flat grid whatever the direction (through vertices and along
// edges, from face points and vertices, with a reoriented face), helices on an open prism
// (a polyhedral cylinder: its side unrolls isometrically onto a strip, so the end point is
// known exactly), the vertex rule on a pyramid's apex, a long ray on an icosphere staying on
// its great circle, and every bad input refused with one clear message.
#include "solvers/recipes/trace_geodesic.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/test_util.h"

namespace ifem::recipes {
namespace {

using intrinsic::kPi;

GivenPoint vertex_point(Index v) {
  GivenPoint p;
  p.vertex = v;
  p.token = "'" + std::to_string(v) + "'";
  return p;
}

// The vertex of `in` at x.
Index vertex_at(const io::SurfaceInput& in, const Eigen::Vector3d& x) {
  for (Index v = 0; v < in.positions.rows(); ++v) {
    if ((in.positions.row(v).transpose() - x).norm() < 1e-12) return v;
  }
  ADD_FAILURE() << "no vertex there";
  return kInvalidIndex;
}

// The face point of `in` at 3D point x (the first face whose plane holds it inside).
GivenPoint face_point_at(const io::SurfaceInput& in, const Eigen::Vector3d& x) {
  for (std::size_t f = 0; f < in.triangles.size(); ++f) {
    const Triangle& t = in.triangles[f];
    const Eigen::Vector3d a = in.positions.row(t[0]), b = in.positions.row(t[1]),
                          c = in.positions.row(t[2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (std::abs((x - a).dot(n.normalized())) > 1e-12) continue;
    const double w1 = (x - a).cross(c - a).dot(n) / n.squaredNorm();
    const double w2 = (b - a).cross(x - a).dot(n) / n.squaredNorm();
    if (w1 < -1e-14 || w2 < -1e-14 || w1 + w2 > 1 + 1e-14) continue;
    GivenPoint p;
    p.face = static_cast<Index>(f);
    p.bary = {1.0 - w1 - w2, w1, w2};
    p.token = "'face:" + std::to_string(f) + "'";
    return p;
  }
  ADD_FAILURE() << "no face holds the point";
  return {};
}

// Largest distance of the polyline's points from the line through a in unit direction d.
double off_line(const std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& a,
                const Eigen::Vector3d& d) {
  double worst = 0.0;
  for (const Eigen::Vector3d& x : poly) {
    const Eigen::Vector3d r = x - a;
    worst = std::max(worst, (r - r.dot(d) * d).norm());
  }
  return worst;
}

// The ray's end point as the face point reports it.
Eigen::Vector3d end_from_bary(const io::SurfaceInput& in, const GeodesicRay& r) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    x += r.end.bary[k] * in.positions.row(in.triangles[r.end.face][k]).transpose();
  }
  return x;
}

TEST(TraceGeodesic, FlatGridStraightLinesOfExactLength) {
  // cells of 0.5 (diagonals alternate): rays from a face point and from a vertex, 48 directions
  // (every 7.5°: along grid lines and cell diagonals, hence through vertices and along edges)
  const io::SurfaceInput in = test::as_input(intrinsic::grid(8, 6, 4.0, 3.0));
  const GeodesicTracer tracer(in);
  const Eigen::Vector3d centre(2.0, 1.5, 0.0);  // a vertex of the grid
  const Index centre_vertex = vertex_at(in, centre);
  const Eigen::Vector3d off(1.7, 1.3, 0.0);  // inside a face
  const GivenPoint starts[2] = {vertex_point(centre_vertex), face_point_at(in, off)};
  const Eigen::Vector3d origins[2] = {centre, off};
  for (int s = 0; s < 2; ++s) {
    for (int k = 0; k < 48; ++k) {
      const double a = k * kPi / 24.0;
      const Eigen::Vector3d d(std::cos(a), std::sin(a), 0.0);
      const double length = 1.2;  // stays inside the 4 × 3 plate
      // a z component is projected away
      const GeodesicRay r = tracer.trace(starts[s], d + Eigen::Vector3d(0, 0, 0.7), length);
      const Eigen::Vector3d want = origins[s] + length * d;
      EXPECT_FALSE(r.hit_boundary);
      EXPECT_NEAR(r.length, length, 1e-12) << s << " " << k;
      EXPECT_NEAR((r.end.position - want).norm(), 0.0, 1e-12) << s << " " << k;
      EXPECT_NEAR((end_from_bary(in, r) - want).norm(), 0.0, 1e-12) << s << " " << k;
      EXPECT_NEAR((r.polyline.back() - want).norm(), 0.0, 1e-12);
      EXPECT_LT(off_line(r.polyline, origins[s], d), 1e-12) << s << " " << k;
      EXPECT_NEAR((r.start_direction - d).norm(), 0.0, 1e-12);
      EXPECT_NEAR((r.end_direction - d).norm(), 0.0, 1e-12);
    }
  }
  // along the x axis from the centre vertex: through vertices every 0.5, ending on one
  const GeodesicRay r = tracer.trace(starts[0], Eigen::Vector3d(1, 0, 0), 1.5);
  EXPECT_EQ(r.end.vertex, vertex_at(in, Eigen::Vector3d(3.5, 1.5, 0)));
  EXPECT_NEAR(r.length, 1.5, 1e-12);
}

TEST(TraceGeodesic, FlatGridBoundaryStopsOrSlides) {
  const io::SurfaceInput in = test::as_input(intrinsic::grid(8, 6, 4.0, 3.0));
  const GeodesicTracer tracer(in);
  const GivenPoint p = face_point_at(in, Eigen::Vector3d(1.7, 1.3, 0.0));
  GeodesicRay r = tracer.trace(p, Eigen::Vector3d(1, 0, 0), 10.0);
  EXPECT_TRUE(r.hit_boundary);
  EXPECT_NEAR(r.length, 2.3, 1e-12);
  EXPECT_NEAR((r.end.position - Eigen::Vector3d(4.0, 1.3, 0.0)).norm(), 0.0, 1e-12);
  // oblique: slides up the side x = 4 to the corner, where the boundary turns back
  TraceGeodesicOptions slide;
  slide.slide_on_boundary = true;
  const Eigen::Vector3d d = Eigen::Vector3d(2.3, 0.5, 0.0).normalized();
  r = tracer.trace(p, d, 10.0, slide);
  EXPECT_GT(r.slides, 0);
  const double to_side = std::hypot(2.3, 0.5);
  EXPECT_NEAR(r.length, to_side + (3.0 - 1.8), 1e-12);
  EXPECT_NEAR((r.end.position - Eigen::Vector3d(4.0, 3.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(r.end.vertex, vertex_at(in, Eigen::Vector3d(4, 3, 0)));
  // a boundary corner: into the plate is fine, off it is refused
  const GivenPoint corner = vertex_point(vertex_at(in, Eigen::Vector3d::Zero()));
  r = tracer.trace(corner, Eigen::Vector3d(3, 1, 0), 1.0);
  EXPECT_NEAR((r.end.position - Eigen::Vector3d(3, 1, 0).normalized()).norm(), 0.0, 1e-12);
  EXPECT_THROW(tracer.trace(corner, Eigen::Vector3d(-1, 0.5, 0), 1.0), InvalidInput);
}

TEST(TraceGeodesic, ReorientedFaceGivesTheSamePoint) {
  io::SurfaceInput in = test::as_input(intrinsic::grid(4, 4, 2.0, 2.0));
  const GivenPoint p = face_point_at(in, Eigen::Vector3d(0.9, 1.15, 0.0));
  const GeodesicRay a = GeodesicTracer(in).trace(p, Eigen::Vector3d(1, 2, 0), 0.7);
  std::swap(in.triangles[p.face][1], in.triangles[p.face][2]);  // the build reorients it back
  GivenPoint q = p;
  std::swap(q.bary[1], q.bary[2]);
  const GeodesicRay b = GeodesicTracer(in).trace(q, Eigen::Vector3d(1, 2, 0), 0.7);
  EXPECT_NEAR((a.end.position - b.end.position).norm(), 0.0, 1e-14);
  EXPECT_NEAR((end_from_bary(in, b) - b.end.position).norm(), 0.0, 1e-14);
}

// An open prism of n sides (circumradius 1) and `rings` rows of height h: its side unrolls onto
// a strip of width n·s (s the side of the n-gon).
struct Prism {
  io::SurfaceInput in;
  int n = 0;
  double s = 0.0, h = 0.0;
  // 3D point of unrolled coordinates (u along the strip, z up)
  Eigen::Vector3d at(double u, double z) const {
    const double w = n * s;
    u = std::fmod(std::fmod(u, w) + w, w);
    const int k = std::min(static_cast<int>(u / s), n - 1);
    const double t = (u - k * s) / s;
    const double a0 = 2 * kPi * k / n, a1 = 2 * kPi * (k + 1) / n;
    const Eigen::Vector3d p0(std::cos(a0), std::sin(a0), z), p1(std::cos(a1), std::sin(a1), z);
    return (1 - t) * p0 + t * p1;
  }
};

Prism prism(int n, int rings, double h) {
  Prism p;
  p.n = n;
  p.h = h;
  p.s = 2 * std::sin(kPi / n);
  p.in.positions.resize(n * (rings + 1), 3);
  for (int i = 0; i <= rings; ++i) {
    for (int j = 0; j < n; ++j) {
      const double a = 2 * kPi * j / n;
      p.in.positions.row(i * n + j) << std::cos(a), std::sin(a), i * h;
    }
  }
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < n; ++j) {
      const Index a = i * n + j, b = i * n + (j + 1) % n, c = a + n, d = b + n;
      p.in.triangles.push_back({a, b, d});
      p.in.triangles.push_back({a, d, c});
    }
  }
  return p;
}

TEST(TraceGeodesic, PrismHelicesUnrollToStraightLines) {
  const Prism p = prism(12, 20, 0.5);  // height 10
  const GeodesicTracer tracer(p.in);
  const double u0 = 0.3 * p.s, z0 = 0.8;
  const GivenPoint start = face_point_at(p.in, p.at(u0, z0));
  const Eigen::Vector3d along = p.at(p.s, 0) - p.at(0, 0);  // panel 0's horizontal, length s
  for (const double climb : {0.05, 0.2, -0.02, 1.0}) {
    // a helix going round about three times (less when it climbs fast)
    const double lu = std::cos(std::atan(climb)), lz = std::sin(std::atan(climb));
    const double length = std::min(3.1 * p.n * p.s, 8.5 / std::max(std::abs(lz), 1e-3));
    const Eigen::Vector3d d = lu * along.normalized() + lz * Eigen::Vector3d::UnitZ();
    const GeodesicRay r = tracer.trace(start, d, length);
    const Eigen::Vector3d want = p.at(u0 + length * lu, z0 + length * lz);
    EXPECT_FALSE(r.hit_boundary) << climb;
    EXPECT_NEAR(r.length, length, 1e-12 * length) << climb;
    EXPECT_NEAR((r.end.position - want).norm(), 0.0, 1e-11) << climb;
  }
  // from a vertex along its vertical edge, along its diagonal edges (the vertex rule's wedges:
  // a uniform scaling of the turn would miss them), and round its ring (a closed geodesic)
  const Index v = 2 * p.n + 5;
  GeodesicRay r = tracer.trace(vertex_point(v), Eigen::Vector3d::UnitZ(), 2 * p.h);
  EXPECT_EQ(r.end.vertex, v + 2 * p.n);
  const Eigen::Vector3d x = p.in.positions.row(v);
  for (const Index w : {v + p.n + 1, v - p.n - 1}) {
    const Eigen::Vector3d e = p.in.positions.row(w).transpose() - x;
    r = tracer.trace(vertex_point(v), e, e.norm());
    EXPECT_EQ(r.end.vertex, w);
    EXPECT_NEAR(r.length, e.norm(), 1e-12);
  }
  const Eigen::Vector3d tangent(-x.y(), x.x(), 0.0);
  r = tracer.trace(vertex_point(v), tangent, p.n * p.s);
  EXPECT_EQ(r.end.vertex, v);
  EXPECT_NEAR(r.length, p.n * p.s, 1e-12);
  EXPECT_LT(off_line({r.end.position}, x, tangent.normalized()), 1e-12);
  double worst_z = 0.0;
  for (const Eigen::Vector3d& y : r.polyline) worst_z = std::max(worst_z, std::abs(y.z() - x.z()));
  EXPECT_LT(worst_z, 1e-12);
}

TEST(TraceGeodesic, ApexDirectionAlongAnEdgeRunsAlongIt) {
  // a square pyramid: the apex is a cone point (angle sum < 2π); a direction along an edge's
  // projection onto the apex's tangent plane runs down that edge to its base corner
  io::SurfaceInput in;
  in.positions.resize(5, 3);
  in.positions << 0, 0, 1.3, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  in.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  const GeodesicTracer tracer(in);
  const double edge = std::hypot(1.0, 1.3);
  for (Index corner = 1; corner <= 4; ++corner) {
    const Eigen::Vector3d d = in.positions.row(corner) - in.positions.row(0);
    const GeodesicRay r = tracer.trace(vertex_point(0), Eigen::Vector3d(d.x(), d.y(), 5.0), edge);
    EXPECT_EQ(r.end.vertex, corner);
    EXPECT_NEAR(r.length, edge, 1e-12);
  }
  // half way between two edges' projections: the middle of the corner between them
  const GeodesicRay r = tracer.trace(vertex_point(0), Eigen::Vector3d(1, 1, 0), edge);
  EXPECT_NEAR(r.end.position.x(), r.end.position.y(), 1e-12);
  EXPECT_TRUE(r.hit_boundary);  // past the base edge, at (0.5, 0.5, 0)
  EXPECT_NEAR((r.end.position - Eigen::Vector3d(0.5, 0.5, 0)).norm(), 0.0, 1e-12);
}

TEST(TraceGeodesic, LongRayOnASphereStaysOnItsGreatCircle) {
  const io::SurfaceInput in = test::as_input(intrinsic::icosphere(24));
  const GeodesicTracer tracer(in);
  const GivenPoint p = vertex_point(0);
  const Eigen::Vector3d x0 = in.positions.row(0);
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(0.3, 1.0, 0.2), Eigen::Vector3d(1, -0.4, 2)}) {
    const Eigen::Vector3d t = (dir - dir.dot(x0) * x0).normalized();
    const Eigen::Vector3d normal = x0.cross(t).normalized();  // of the great circle's plane
    const double length = 2 * kPi;                            // once round (a bit more: inscribed)
    const GeodesicRay r = tracer.trace(p, dir, length);
    EXPECT_NEAR(r.length, length, 1e-12 * length);
    double off_plane = 0.0, to_start = 10.0;
    for (std::size_t i = 0; i < r.polyline.size(); ++i) {
      off_plane = std::max(off_plane, std::abs(r.polyline[i].dot(normal)));
      if (i > r.polyline.size() / 2) to_start = std::min(to_start, (r.polyline[i] - x0).norm());
    }
    EXPECT_LT(off_plane, 0.02);  // the polyhedral geodesic drifts a little off the circle
    EXPECT_LT(to_start, 0.02);   // and comes back past the start
  }
}

TEST(TraceGeodesic, RaysOnACurvedMeshTraceBackToTheirStart) {
  // spot (bundled, 5856 faces, closed): a ray from a random face point, then the ray from its
  // end in the reverse of its end direction, comes back to the start (unfolding is exact up to
  // rounding away from vertices); lengths are the ones asked
  const io::SurfaceInput in = io::read_surface(std::string(IFEM_TEST_DATA) + "/spot.obj");
  const GeodesicTracer tracer(in);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss;
  for (int i = 0; i < 30; ++i) {
    GivenPoint p;
    p.face = static_cast<Index>(unit(rng) * static_cast<double>(in.triangles.size()));
    const double u = 0.1 + 0.4 * unit(rng), v = 0.1 + 0.4 * unit(rng);
    p.bary = {1.0 - u - v, u, v};
    p.token = "random";
    const Eigen::Vector3d d(gauss(rng), gauss(rng), gauss(rng));
    const double length = 0.2 + unit(rng);
    const GeodesicRay r = tracer.trace(p, d, length);
    ASSERT_NEAR(r.length, length, 1e-12 * length) << i;
    GivenPoint q;
    q.face = r.end.face;
    q.bary = r.end.bary;
    q.token = "end";
    const GeodesicRay back = tracer.trace(q, -r.end_direction, length);
    EXPECT_NEAR((back.end.position - r.polyline.front()).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR((back.end_direction + r.start_direction).norm(), 0.0, 1e-8) << i;
  }
}

// One clear message per bad input, each naming what is wrong.
void expect_invalid(const GeodesicTracer& tracer, const GivenPoint& p, const Eigen::Vector3d& d,
                    double length, const std::string& part) {
  try {
    tracer.trace(p, d, length);
    ADD_FAILURE() << "accepted: " << part;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(TraceGeodesic, BadInputsAreRefused) {
  const io::SurfaceInput in = test::as_input(intrinsic::grid(4, 4, 2.0, 2.0));
  const GeodesicTracer tracer(in);
  const GivenPoint p = face_point_at(in, Eigen::Vector3d(0.9, 1.15, 0.0));
  expect_invalid(tracer, p, Eigen::Vector3d::Zero(), 1.0, "nonzero");
  expect_invalid(tracer, p, Eigen::Vector3d(0, 0, 1), 1.0, "along the surface normal");
  const GivenPoint middle = vertex_point(vertex_at(in, Eigen::Vector3d(1, 1, 0)));
  expect_invalid(tracer, middle, Eigen::Vector3d(1e-12, 0, -1), 1.0, "normal");
  expect_invalid(tracer, p, Eigen::Vector3d(1, 0, 0), -1.0, "length");
  expect_invalid(tracer, p, Eigen::Vector3d(NAN, 0, 0), 1.0, "finite");
  expect_invalid(tracer, vertex_point(25), Eigen::Vector3d(1, 0, 0), 1.0, "out of range");
  GivenPoint bad = p;
  bad.face = 32;
  expect_invalid(tracer, bad, Eigen::Vector3d(1, 0, 0), 1.0, "out of range");
  const GivenPoint edge = vertex_point(vertex_at(in, Eigen::Vector3d(1, 0, 0)));
  expect_invalid(tracer, edge, Eigen::Vector3d(0.3, -1, 0), 1.0, "off the surface");
  // a pinched vertex (two fans), a nonmanifold edge, a point cloud
  io::SurfaceInput bowtie;
  bowtie.positions.resize(5, 3);
  bowtie.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  bowtie.triangles = {{0, 1, 2}, {0, 3, 4}};
  expect_invalid(GeodesicTracer(bowtie), vertex_point(0), Eigen::Vector3d(1, 1, 0), 0.1, "pinched");
  io::SurfaceInput fin = bowtie;
  fin.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_THROW(GeodesicTracer{fin}, NonManifoldInput);
  io::SurfaceInput cloud;
  cloud.positions = bowtie.positions;
  EXPECT_THROW(GeodesicTracer{cloud}, InvalidInput);
}

TEST(TraceGeodesic, DirectionTokens) {
  Eigen::Vector3d d;
  EXPECT_EQ(parse_direction("1,-2.5,3e-1", d), "");
  EXPECT_EQ(d, Eigen::Vector3d(1, -2.5, 0.3));
  EXPECT_NE(parse_direction("1,2", d).find("X,Y,Z"), std::string::npos);
  EXPECT_NE(parse_direction("1,2,nan", d).find("X,Y,Z"), std::string::npos);
  EXPECT_NE(parse_direction("0,0,0", d).find("zero direction"), std::string::npos);
  InputSurfacePoint q;
  q.face = 7;
  q.bary = {0.5, 0.25, 0.25};
  EXPECT_EQ(q.token(), "face:7:0.25:0.25");
}

}  // namespace
}  // namespace ifem::recipes
