// The geodesic recipe (solvers/recipes/geodesic.h) where FlipOut cannot go or falls short
// (docs/decisions.md D-375): paths between two points and single-source geodesics on
// nonmanifold inputs through the tufted cover (a generated book of flat pages, against the
// pages unfolded into one plane; conrod against ../shared/data/reference), the refusals of
// what needs signposts there, and a pair path never longer than the exact distance (rocketship
// pairs where FlipOut's geodesic is held longer).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/io/mesh_io.h"
#include "solvers/recipes/geodesic.h"

namespace ifem::recipes {
namespace {

namespace fs = std::filesystem;

constexpr int kBookCells = 4;  // nx = ny: cells across and up each page (unit pages)

io::SurfaceInput book_input(int pages) {
  const intrinsic::TriangleMesh m = intrinsic::book(pages, kBookCells, kBookCells);
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  return in;
}

// Vertex (i, j) of page p (i across from the spine, j up), as intrinsic::book() numbers them.
Index book_vertex(int p, int i, int j) {
  const Index column = kBookCells + 1;
  return i == 0 ? Index(j) : column + (Index(p) * kBookCells + (i - 1)) * column + j;
}

// (page, u, z) of a point of the book (u: distance from the spine); page −1 when the point is
// on no page (farther than 1e-12 from every page's half-plane or outside its rectangle).
struct BookPlace {
  int page = -1;
  double u = 0.0, z = 0.0;
};

BookPlace book_place(const Eigen::Vector3d& x, int pages) {
  BookPlace best;
  for (int p = 0; p < pages; ++p) {
    const double angle = 2.0 * intrinsic::kPi * p / pages;
    const Eigen::Vector3d d(std::cos(angle), std::sin(angle), 0.0);
    const double u = x.dot(d);
    const Eigen::Vector3d off = x - u * d - x.z() * Eigen::Vector3d::UnitZ();
    if (off.norm() <= 1e-12 && u >= -1e-12 && u <= 1.0 + 1e-12 && x.z() >= -1e-12 &&
        x.z() <= 1.0 + 1e-12) {
      return {p, std::max(u, 0.0), x.z()};
    }
  }
  return best;
}

// The shortest path on the book between two of its points: straight on one page, else straight
// on the two pages unfolded into one plane (it crosses the spine between their heights).
double book_distance(const BookPlace& a, const BookPlace& b) {
  if (a.page == b.page) return std::hypot(a.u - b.u, a.z - b.z);
  return std::hypot(a.u + b.u, a.z - b.z);
}

double polyline_length(const std::vector<Eigen::Vector3d>& line) {
  double s = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) s += (line[i] - line[i - 1]).norm();
  return s;
}

// Every point of the polyline on some page, its length the reported one, its ends the points.
void expect_on_book(const std::vector<Eigen::Vector3d>& line, int pages, double length,
                    const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                    const std::string& what) {
  ASSERT_GE(line.size(), 2u) << what;
  for (const Eigen::Vector3d& x : line) EXPECT_GE(book_place(x, pages).page, 0) << what;
  EXPECT_NEAR(polyline_length(line), length, 1e-12) << what;
  EXPECT_LT((line.front() - from).norm(), 1e-12) << what;
  EXPECT_LT((line.back() - to).norm(), 1e-12) << what;
}

GivenPoint book_point_vertex(Index v) {
  GivenPoint p;
  p.vertex = v;
  p.token = "'" + std::to_string(v) + "'";
  return p;
}

GivenPoint book_point_face(Index f, double b0, double b1, double b2) {
  GivenPoint p;
  p.face = f;
  p.bary = {b0, b1, b2};
  p.token = "'face:" + std::to_string(f) + "'";
  return p;
}

Eigen::Vector3d given_position(const io::SurfaceInput& in, const GivenPoint& p) {
  if (p.vertex != kInvalidIndex) return in.positions.row(p.vertex).transpose();
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int j = 0; j < 3; ++j) {
    x += p.bary[j] * in.positions.row(in.triangles[std::size_t(p.face)][j]).transpose();
  }
  return x;
}

GivenCurve book_curve(std::vector<GivenPoint> points) {
  GivenCurve c;
  c.origin = "--path";
  c.points = std::move(points);
  return c;
}

// A face of page p (the first face of its cell (i, j)).
Index book_face(int p, int i, int j) {
  return 2 * (Index(p) * kBookCells * kBookCells + Index(i) * kBookCells + j);
}

TEST(GeodesicCover, BookPathsAreThePagesUnfolded) {
  const io::SurfaceInput in = book_input(3);  // 3 pages: every two pages meet across the spine
  const std::vector<std::vector<GivenPoint>> pairs = {
      {book_point_vertex(book_vertex(0, 4, 1)), book_point_vertex(book_vertex(1, 3, 3))},
      {book_point_vertex(book_vertex(2, 1, 4)), book_point_vertex(book_vertex(0, 2, 0))},
      {book_point_vertex(book_vertex(0, 2, 2)), book_point_vertex(book_vertex(0, 4, 4))},
      {book_point_vertex(book_vertex(1, 4, 0)), book_point_face(book_face(2, 3, 2), 0.2, 0.3, 0.5)},
      {book_point_face(book_face(0, 1, 0), 0.6, 0.3, 0.1), book_point_vertex(book_vertex(2, 4, 4))},
      {book_point_face(book_face(1, 2, 3), 0.1, 0.1, 0.8),
       book_point_face(book_face(2, 0, 0), 0.3, 0.3, 0.4)},
      // on a face side (traced from the other end), both on sides, on the spine (the side of
      // face (0, 0, 1) from its corner 0 to 2), and two points of one face
      {book_point_face(book_face(1, 3, 1), 0.5, 0.5, 0.0),
       book_point_face(book_face(0, 2, 2), 0.2, 0.2, 0.6)},
      {book_point_face(book_face(0, 1, 1), 0.5, 0.5, 0.0),
       book_point_face(book_face(1, 1, 1), 0.0, 0.5, 0.5)},
      {book_point_face(book_face(0, 0, 1), 0.4, 0.0, 0.6), book_point_vertex(book_vertex(2, 3, 0))},
      {book_point_face(book_face(1, 2, 2), 0.3, 0.3, 0.4),
       book_point_face(book_face(0, 0, 1), 0.4, 0.0, 0.6)},
      {book_point_face(book_face(0, 0, 1), 0.4, 0.0, 0.6),
       book_point_face(book_face(2, 3, 3), 0.0, 0.7, 0.3)},
      {book_point_face(book_face(2, 3, 3), 0.0, 0.7, 0.3),
       book_point_face(book_face(0, 0, 1), 0.4, 0.0, 0.6)},
      // the diagonal of cell (1, 1) of page 0 (its faces' shared side) and another side of the
      // second face: splitting the diagonal would rewrite the other point's face
      {book_point_face(book_face(0, 1, 1) + 1, 0.0, 0.4, 0.6),
       book_point_face(book_face(0, 1, 1), 0.3, 0.0, 0.7)},
      {book_point_face(book_face(1, 3, 1), 0.7, 0.2, 0.1),
       book_point_face(book_face(1, 3, 1), 0.1, 0.2, 0.7)},
  };
  for (const auto& points : pairs) {
    const GeodesicCurves run = geodesic(in, {book_curve(points)});
    const std::string what = points[0].token + " → " + points[1].token;
    ASSERT_TRUE(run.tufted_cover) << what;
    EXPECT_EQ(run.start_won, "exact path (tufted cover)") << what;
    const Eigen::Vector3d a = given_position(in, points[0]), b = given_position(in, points[1]);
    const double analytic = book_distance(book_place(a, 3), book_place(b, 3));
    ASSERT_EQ(run.curves.size(), 1u);
    EXPECT_NEAR(run.curves[0].length, analytic, 1e-12) << what;
    expect_on_book(run.curves[0].polyline, 3, run.curves[0].length, a, b, what);
  }
}

// Around the spine of 4 pages the cover glues neighbouring pages only: between opposite pages
// the path is still on the book and never shorter than the unfolded line, but it goes through
// a spine vertex (documented in geodesic.h and `ifem geodesic --help`).
TEST(GeodesicCover, BookOfFourPagesOppositePagesMeetAtASpineVertex) {
  const io::SurfaceInput in = book_input(4);
  const GivenPoint a = book_point_vertex(book_vertex(0, 4, 1));
  for (const int page : {1, 2}) {
    const GivenPoint b = book_point_vertex(book_vertex(page, 3, 3));
    const GeodesicCurves run = geodesic(in, {book_curve({a, b})});
    const Eigen::Vector3d x = given_position(in, a), y = given_position(in, b);
    const double analytic = book_distance(book_place(x, 4), book_place(y, 4));
    const double length = run.curves[0].length;
    if (page == 1) {
      EXPECT_NEAR(length, analytic, 1e-12);
    } else {  // through the spine vertex nearest the line, z = 0.5: 2·hypot(1 or 0.75, ...)
      const double via_vertex = std::hypot(1.0, 0.25) + std::hypot(0.75, 0.25);
      EXPECT_GT(length, analytic + 1e-4);
      EXPECT_NEAR(length, via_vertex, 1e-12);
    }
    expect_on_book(run.curves[0].polyline, 4, length, x, y, "page " + std::to_string(page));
  }
}

TEST(GeodesicCover, BookSingleSourceLengthsAndPaths) {
  const io::SurfaceInput in = book_input(3);
  const Index source = book_vertex(1, 2, 1);
  GeodesicOptions o;
  o.trace_paths = true;
  const SingleSourceResult r = geodesic(in, source, o);
  ASSERT_TRUE(r.exact);
  ASSERT_TRUE(r.tufted_cover);
  ASSERT_EQ(r.length.size(), in.positions.rows());
  ASSERT_EQ(r.paths.size(), std::size_t(in.positions.rows()));
  const Eigen::Vector3d s = in.positions.row(source).transpose();
  for (Index v = 0; v < in.positions.rows(); ++v) {
    const Eigen::Vector3d x = in.positions.row(v).transpose();
    const double analytic = book_distance(book_place(s, 3), book_place(x, 3));
    EXPECT_NEAR(r.length[v], analytic, 1e-12) << v;
    if (v == source) {
      EXPECT_EQ(r.paths[std::size_t(v)].size(), 1u);
    } else {
      expect_on_book(r.paths[std::size_t(v)], 3, r.length[v], s, x, std::to_string(v));
    }
  }
}

TEST(GeodesicCover, WhatNeedsSignpostsIsRefusedWithTheReason) {
  const io::SurfaceInput in = book_input(3);
  const auto refused = [&](const std::vector<GivenCurve>& curves, const GeodesicOptions& o,
                           const std::string& what) {
    try {
      geodesic(in, curves, o);
      ADD_FAILURE() << what << " accepted on a nonmanifold mesh";
    } catch (const NonManifoldInput& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(what + " needs FlipOut"), std::string::npos) << m;
      EXPECT_NE(m.find("(faces"), std::string::npos) << m;  // the offending edge's faces
      EXPECT_NE(m.find("--path A,B"), std::string::npos) << m;
      EXPECT_NE(m.find("--all-from"), std::string::npos) << m;
    }
  };
  const GivenPoint a = book_point_vertex(book_vertex(0, 4, 1)),
                   b = book_point_vertex(book_vertex(1, 3, 3)),
                   c = book_point_vertex(book_vertex(2, 3, 3));
  refused({book_curve({a, b, c})}, {}, "a path through more than two points");
  GivenCurve loop = book_curve({a, b, c});
  loop.closed = true;
  refused({loop}, {}, "a loop");
  refused({book_curve({a, b}), book_curve({b, c})}, {}, "a network of curves");
  GeodesicOptions bezier;
  bezier.bezier_rounds = 2;
  refused({book_curve({a, b, c})}, bezier, "a Bézier curve");
  GeodesicOptions flipout;
  flipout.single_source_flipout = true;
  try {
    geodesic(in, Index{0}, flipout);
    ADD_FAILURE() << "single-source FlipOut accepted on a nonmanifold mesh";
  } catch (const NonManifoldInput& e) {
    EXPECT_NE(std::string(e.what()).find("need signposts"), std::string::npos) << e.what();
  }
}

// conrod (nonmanifold: 4 faces at some edges) against its exact references: single-source
// lengths on every finite vertex, and pair paths to the source.
TEST(GeodesicCover, ConrodAgainstTheReferences) {
  IFEM_REQUIRE_SHARED_DATA();
  const fs::path mesh = test::shared_data() / "meshes" / "conrod.off";
  ASSERT_TRUE(fs::exists(mesh)) << mesh << ": ../shared/data is present, its conrod.off is not";
  const io::SurfaceInput in = io::read_mesh(mesh.string());
  int checked = 0;
  for (const Index src : {0, 7}) {
    const fs::path ref =
        test::shared_data() / "reference" / ("conrod.src" + std::to_string(src) + ".exact.txt");
    ASSERT_TRUE(fs::exists(ref)) << ref;
    const Eigen::VectorXd exact = io::read_values(ref.string());
    const SingleSourceResult r = geodesic(in, src);
    ASSERT_TRUE(r.tufted_cover);
    ASSERT_EQ(r.length.size(), exact.size());
    for (Index v = 0; v < exact.size(); ++v) {
      if (!std::isfinite(exact[v])) continue;
      EXPECT_NEAR(r.length[v], exact[v], 1e-9 * std::max(exact[v], 1.0)) << src << " → " << v;
      ++checked;
    }
    for (int k = 1; k <= 3; ++k) {
      const Index v = (k * 7919) % Index(exact.size());
      if (v == src || !std::isfinite(exact[v])) continue;
      const GeodesicCurves run =
          geodesic(in, {book_curve({book_point_vertex(v), book_point_vertex(src)})});
      EXPECT_NEAR(run.curves[0].length, exact[v], 1e-9 * exact[v]) << v << " → " << src;
      EXPECT_NEAR(polyline_length(run.curves[0].polyline), exact[v], 1e-9 * exact[v]);
      ++checked;
    }
  }
  EXPECT_GT(checked, 6000);
}

// FlipOut's kept geodesic is held longer on these rocketship pairs (docs/decisions.md D-150,
// D-375: 3.5e-3, 4.4e-3 and 5.8e-4 before): the exact path is returned instead.
TEST(GeodesicExactPairs, RocketshipPairsAreNeverLongerThanExact) {
  IFEM_REQUIRE_SHARED_DATA();
  const fs::path mesh = test::shared_data() / "meshes" / "rocketship.ply";
  const fs::path ref = test::shared_data() / "reference" / "rocketship.src0.exact.txt";
  ASSERT_TRUE(fs::exists(mesh) && fs::exists(ref)) << "../shared/data lacks rocketship";
  const io::SurfaceInput in = io::read_mesh(mesh.string());
  const Eigen::VectorXd exact = io::read_values(ref.string());
  GeodesicOptions o;
  o.mollify_relative_epsilon = 0.0;  // the reference's lengths
  int fallbacks = 0;
  for (const Index v : {15838, 3666, 19504}) {
    const GeodesicCurves run =
        geodesic(in, {book_curve({book_point_vertex(v), book_point_vertex(0)})}, o);
    const double length = run.curves[0].length;
    EXPECT_LE(length, exact[v] * (1.0 + 1e-9)) << v << ": " << run.start_won;
    EXPECT_NEAR(length, exact[v], 1e-9 * exact[v]) << v;
    EXPECT_NEAR(polyline_length(run.curves[0].polyline), length, 1e-9 * length) << v;
    EXPECT_LT((run.curves[0].polyline.front() - in.positions.row(v).transpose()).norm(), 1e-9);
    EXPECT_LT((run.curves[0].polyline.back() - in.positions.row(0).transpose()).norm(), 1e-9);
    fallbacks += run.start_won.rfind("exact path (FlipOut's geodesic from ", 0) == 0;
  }
  EXPECT_EQ(fallbacks, 3);  // else FlipOut found these itself: pick pairs it still misses
}

// A grid of nx×ny cells over [0, W]×[0, H] (alternating diagonals) with random heights: a sum
// of three hashed uniforms, so many saddle vertices. Its own hash (no library generator), so
// the cases below stay the cases FlipOut misses.
double bumpy_hash01(std::uint64_t i, std::uint64_t j, std::uint64_t seed) {
  std::uint32_t h =
      static_cast<std::uint32_t>((i * 73856093u) ^ (j * 19349663u) ^ (seed * 83492791u));
  for (int k = 0; k < 3; ++k) {
    h ^= h << 13;
    h ^= h >> 17;
    h ^= h << 5;
  }
  return h / 4294967296.0;
}

io::SurfaceInput bumpy_grid(int nx, int ny, double w, double h, double amp, int seed) {
  io::SurfaceInput in;
  in.positions.resize((nx + 1) * (ny + 1), 3);
  const auto id = [&](int i, int j) { return Index(i * (ny + 1) + j); };
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      double z = -1.5;
      for (const int s : {seed, seed + 7777, seed + 15555}) z += bumpy_hash01(i, j, s);
      in.positions.row(id(i, j)) << w * i / nx, h * j / ny, amp * z;
    }
  }
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      intrinsic::add_quad(in.triangles, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1),
                          (i + j) % 2 == 0);
    }
  }
  return in;
}

// Small generated cases where every start of `start = best` ends at a geodesic held longer at
// saddle vertices (found by a search over seeds; FlipOut's excess in the comment): the exact
// path is returned, as long as the exact distance (single-source, the same lengths).
TEST(GeodesicExactPairs, BumpyGridPairsAreNeverLongerThanExact) {
  struct Case {
    int nx, ny;
    double w, amp;
    int seed;
    Index a, b;
  };
  const Case cases[] = {
      {10, 10, 1.0, 0.1, 263, 7, 89},    // +1.1e-3
      {12, 12, 1.0, 0.06, 302, 85, 34},  // +4.8e-3
      {30, 6, 10.0, 0.3, 78, 59, 208},   // +2.9e-3
  };
  for (const Case& c : cases) {
    const io::SurfaceInput in = bumpy_grid(c.nx, c.ny, c.w, 1.0, c.amp, c.seed);
    const std::string what = "seed " + std::to_string(c.seed);
    const GeodesicCurves run =
        geodesic(in, {book_curve({book_point_vertex(c.a), book_point_vertex(c.b)})});
    const double exact = geodesic(in, c.b).length[c.a];
    EXPECT_EQ(run.start_won.rfind("exact path (FlipOut's geodesic from ", 0), 0u)
        << what << ": " << run.start_won << " (FlipOut found it: pick another case)";
    EXPECT_LE(run.curves[0].length, exact * (1.0 + kExactPairTolerance)) << what;
    EXPECT_NEAR(run.curves[0].length, exact, 1e-12 * exact) << what;
    EXPECT_NEAR(polyline_length(run.curves[0].polyline), exact, 1e-12 * exact) << what;
    EXPECT_LT((run.curves[0].polyline.front() - in.positions.row(c.a).transpose()).norm(), 1e-12);
    EXPECT_LT((run.curves[0].polyline.back() - in.positions.row(c.b).transpose()).norm(), 1e-12);
    // the Dijkstra start alone has no exact distance to compare with: FlipOut's geodesic as is
    intrinsic::StartPath dijkstra = intrinsic::StartPath::kDijkstra;
    GeodesicOptions o;
    o.start = dijkstra;
    const GeodesicCurves plain =
        geodesic(in, {book_curve({book_point_vertex(c.a), book_point_vertex(c.b)})}, o);
    EXPECT_GE(plain.curves[0].length, exact * (1.0 - 1e-12)) << what;
    EXPECT_EQ(plain.start_won, "") << what;
  }
}

}  // namespace
}  // namespace ifem::recipes
