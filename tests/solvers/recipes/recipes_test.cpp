// The recipes' text formats (solvers/recipes/text_formats.h, the curves-file writer of
// curves.h), the geodesic recipe (geodesic.h) against straight lines on a flat grid, and the
// options structs that gained validate(): every bad line rejected at FILE:line, every format
// read back as written.
#include "solvers/recipes/recipes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "solvers/recipes/curves.h"
#include "solvers/recipes/geodesic.h"
#include "solvers/recipes/text_formats.h"

namespace ifem::recipes {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Files in the temp directory, removed at the end of each test (names unique per test).
class RecipeFormats : public ::testing::Test {
 protected:
  std::string write(const std::string& text) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() / ("ifem_recipes_" + std::string(info->name()) +
                                                  "_" + std::to_string(files_.size()) + ".txt");
    std::ofstream(p) << text;
    files_.push_back(p);
    return p.string();
  }
  void TearDown() override {
    for (const auto& p : files_) std::filesystem::remove(p);
  }
  // Expects read(file with text) to throw E whose message has "FILE:line: " and `expected`.
  template <class E, class Read>
  void expect_error(const std::string& text, int line, const std::string& expected, Read read) {
    const std::string p = write(text);
    try {
      read(p);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const E& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(p + ":" + std::to_string(line) + ": "), std::string::npos) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
    }
  }

 private:
  std::vector<std::filesystem::path> files_;
};

TEST_F(RecipeFormats, VertexList) {
  const std::string p = write("# sources\n3\n\n7  # the tip\n3\n");
  const std::vector<ListedVertex> l = read_vertex_list(p);
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[0].vertex, 3);
  EXPECT_EQ(l[1].vertex, 7);
  EXPECT_EQ(l[1].line, 4);
  EXPECT_EQ(checked_vertex_ids(p, l, 8), (std::vector<Index>{3, 7, 3}));
  try {
    checked_vertex_ids(p, l, 7);
    ADD_FAILURE() << "vertex 7 of 7 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(p + ":4: vertex 7 out of range [0, 7)"), std::string::npos)
        << e.what();
  }
  for (const char* bad : {"1 2\n", "-1\n", "x\n", "2.5\n", "99999999999\n"}) {
    expect_error<IoError>(std::string("0\n") + bad, 2, "expected one vertex id", read_vertex_list);
  }
  EXPECT_THROW(read_vertex_list(write("# nothing\n")), InvalidInput);
  EXPECT_THROW(read_vertex_list("/nonexistent/ifem_sources.txt"), IoError);
}

TEST_F(RecipeFormats, DirichletFile) {
  const DirichletValues d = read_dirichlet_file(write("0 1.5\n# c\n4 -2e-3\n"), 5);
  EXPECT_EQ(d.vertices, (std::vector<Index>{0, 4}));
  ASSERT_EQ(d.values.size(), 2);
  EXPECT_EQ(d.values[0], 1.5);
  EXPECT_EQ(d.values[1], -2e-3);
  EXPECT_EQ(read_dirichlet_file(write("\n# none\n"), 5).vertices.size(), 0u);
  const auto read5 = [](const std::string& p) { return read_dirichlet_file(p, 5); };
  for (const char* bad : {"1\n", "1 2 3\n", "x 1\n", "1 nan\n", "1 inf\n"}) {
    expect_error<IoError>(std::string("0 0\n") + bad, 2, "expected 'vertex value'", read5);
  }
  expect_error<InvalidInput>("0 0\n5 1\n", 2, "vertex 5 out of range [0, 5)", read5);
  expect_error<InvalidInput>("-1 1\n", 1, "out of range", read5);
}

TEST_F(RecipeFormats, ConstraintsFile) {
  const std::vector<solvers::InputDirection> c =
      read_constraints_file(write("2 1 0 0\n# x\n5 0 0.5 1  # tilted\n"));
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[1].vertex, 5);
  EXPECT_EQ(c[1].direction, Eigen::Vector3d(0, 0.5, 1));
  for (const char* bad : {"1 0 0\n", "1 0 0 0 0\n", "-1 1 0 0\n", "1 x 0 0\n", "1 nan 0 0\n"}) {
    expect_error<IoError>(std::string("0 1 0 0\n") + bad, 2, "expected 'VERTEX X Y Z'",
                          read_constraints_file);
  }
}

TEST_F(RecipeFormats, NetworkFile) {
  const std::vector<GivenCurve> n =
      read_network_file(write("# net\npath 0 face:3:0.25:0.5 9\n\nloop 1 2 3  # a loop\n"), true);
  ASSERT_EQ(n.size(), 2u);
  EXPECT_FALSE(n[0].closed);
  EXPECT_TRUE(n[1].closed);
  EXPECT_TRUE(n[1].pin);
  ASSERT_EQ(n[0].points.size(), 3u);
  const GivenPoint& f = n[0].points[1];
  EXPECT_EQ(f.vertex, kInvalidIndex);
  EXPECT_EQ(f.face, 3);
  EXPECT_DOUBLE_EQ(f.bary[0], 0.25);
  EXPECT_EQ(f.bary[1], 0.25);
  EXPECT_EQ(f.bary[2], 0.5);
  EXPECT_NE(n[1].origin.find(":4"), std::string::npos) << n[1].origin;
  EXPECT_FALSE(read_network_file(write("loop 1 2 3\n"), false)[0].pin);
  const auto read = [](const std::string& p) { return read_network_file(p, false); };
  // u + v > 1 is refused (the CLI's rule; Python used to clamp it)
  expect_error<IoError>("path 0 1\npath 0 face:1:0.7:0.7\n", 2, "u + v ≤ 1", read);
  expect_error<IoError>("path 0 face:1:-0.1:0.2\n", 1, "u + v ≤ 1", read);
  expect_error<IoError>("curve 0 1\n", 1, "expected 'path P0 P1 ...'", read);
  expect_error<IoError>("path 0\n", 1, "at least two", read);
  expect_error<IoError>("path 0 x\n", 1, "'x' is not a point", read);
  expect_error<IoError>("path 0 face:1:x:0\n", 1, "'face:1:x:0' is not a point", read);
  expect_error<IoError>("path 3 3\n", 1, "same point", read);
  expect_error<IoError>("loop 4 5 4\n", 1, "points 3 and 1 are the same point", read);
  try {
    read(write("# only a comment\n"));
    ADD_FAILURE() << "an empty network accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("no curves"), std::string::npos) << e.what();
  }
}

TEST_F(RecipeFormats, CurvesFileWrittenAndReadBack) {
  using solvers::CurveCondition;
  std::vector<CurveCondition> curves(4);
  curves[0].vertices = {12, 40, 77};
  curves[0].values = {0.1 + 0.2};
  curves[1].vertices = {5, 9, 13};
  curves[1].shape = intrinsic::CurveShape::kLoop;
  curves[1].values = {1, -2.5, 1e-300};
  curves[2].vertices = {3, 8, 20, 31};
  curves[2].shape = intrinsic::CurveShape::kBezier;
  curves[2].bezier_rounds = 6;
  curves[2].values = {0, 1};
  curves[3].vertices = {12, 77};
  curves[3].slit = true;
  curves[3].values = {0, 1};
  curves[3].right_values = {1, 0};
  EXPECT_EQ(solvers::curve_line(curves[0]), "0.30000000000000004 12 40 77");
  EXPECT_EQ(solvers::curve_line(curves[2]), "bezier=6 0.0 1.0 : 3 8 20 31");
  EXPECT_EQ(solvers::curve_line(curves[3]), "slit 0.0 1.0 : 1.0 0.0 : 12 77");
  const std::string p = write("");
  solvers::write_curves_file(p, curves);
  const std::vector<CurveCondition> back = solvers::read_curves_file(p);
  ASSERT_EQ(back.size(), curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    EXPECT_EQ(back[c].vertices, curves[c].vertices) << c;
    EXPECT_EQ(back[c].shape, curves[c].shape) << c;
    EXPECT_EQ(back[c].values, curves[c].values) << c;  // exact: the text reads back bit for bit
    EXPECT_EQ(back[c].right_values, curves[c].right_values) << c;
    EXPECT_EQ(back[c].slit, curves[c].slit) << c;
    EXPECT_EQ(back[c].origin, p + ":" + std::to_string(c + 1));
  }
  EXPECT_EQ(back[2].bezier_rounds, 6);
  CurveCondition bare;
  bare.vertices = {1, 2};
  bare.origin = "curves[3]";
  EXPECT_THROW(solvers::curve_line(bare), InvalidInput);
}

// A flat 8×8 grid of the unit square: geodesics are straight lines.
io::SurfaceInput flat_grid() {
  const intrinsic::TriangleMesh m = intrinsic::grid(8, 8);
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  return in;
}

Index vertex_at(const io::SurfaceInput& in, double x, double y) {
  for (Index v = 0; v < in.positions.rows(); ++v) {
    if (std::abs(in.positions(v, 0) - x) < 1e-12 && std::abs(in.positions(v, 1) - y) < 1e-12) {
      return v;
    }
  }
  ADD_FAILURE() << "no vertex at " << x << ", " << y;
  return 0;
}

GivenPoint at_vertex(Index v) {
  GivenPoint p;
  p.vertex = v;
  p.token = "'" + std::to_string(v) + "'";
  return p;
}

TEST(RecipeGeodesic, StraightLinesOnAFlatGrid) {
  const io::SurfaceInput in = flat_grid();
  const Index a = vertex_at(in, 0, 0), b = vertex_at(in, 1, 0.625);
  GivenCurve c;
  c.origin = "test";
  c.points = {at_vertex(a), at_vertex(b)};
  // a face point: the centroid of face 20
  GivenPoint f;
  f.face = 20;
  f.bary = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  f.token = "'centroid'";
  GivenCurve d;
  d.origin = "test2";
  d.points = {at_vertex(a), f};
  const GeodesicCurves run = geodesic(in, {c, d});
  ASSERT_EQ(run.curves.size(), 2u);
  const double exact = std::hypot(1.0, 0.625);
  EXPECT_NEAR(run.curves[0].length, exact, 1e-12);
  EXPECT_GE(run.curves[0].initial_length, exact - 1e-12);
  const Eigen::RowVector3d centroid =
      (in.positions.row(in.triangles[20][0]) + in.positions.row(in.triangles[20][1]) +
       in.positions.row(in.triangles[20][2])) /
      3.0;
  EXPECT_NEAR(run.curves[1].length, (centroid - in.positions.row(a)).norm(), 1e-9);
  ASSERT_EQ(run.inserted.size(), 1u);
  EXPECT_LT((run.inserted[0].position - centroid.transpose()).norm(), 1e-12);
  // every polyline point lies on the segment's line, the ends at the given points
  const std::vector<Eigen::Vector3d>& line = run.curves[0].polyline;
  ASSERT_GE(line.size(), 2u);
  EXPECT_LT((line.front() - in.positions.row(a).transpose()).norm(), 1e-12);
  EXPECT_LT((line.back() - in.positions.row(b).transpose()).norm(), 1e-12);
  for (const Eigen::Vector3d& x : line) EXPECT_NEAR(x.y(), 0.625 * x.x(), 1e-12);
}

TEST(RecipeGeodesic, SingleSourceLengthsAreEuclidean) {
  const io::SurfaceInput in = flat_grid();
  const Index s = vertex_at(in, 0.25, 0.5);
  GeodesicOptions o;
  o.trace_paths = true;
  // Default: the exact distance, the straight line to every vertex, traced straight.
  const SingleSourceResult e = geodesic(in, s, o);
  ASSERT_TRUE(e.exact);
  ASSERT_EQ(e.paths.size(), static_cast<std::size_t>(in.positions.rows()));
  for (Index v = 0; v < in.positions.rows(); ++v) {
    const Eigen::Vector3d a = in.positions.row(s), b = in.positions.row(v);
    EXPECT_NEAR(e.length[v], (b - a).norm(), 1e-12) << v;
    const std::vector<Eigen::Vector3d>& line = e.paths[static_cast<std::size_t>(v)];
    EXPECT_LT((line.front() - a).norm(), 1e-15);
    EXPECT_LT((line.back() - b).norm(), 1e-15);
    for (const Eigen::Vector3d& x : line) EXPECT_LT((x - a).cross(b - a).norm(), 1e-12) << v;
  }
  // Over the memory budget, and on request: FlipOut. Flat and convex: the geodesic is the
  // straight line, found for nearly every vertex (a path left bent by an earlier one is
  // longer, never shorter).
  for (const bool on_request : {false, true}) {
    GeodesicOptions f = o;
    f.single_source_flipout = on_request;
    f.max_memory_bytes = on_request ? 0.0 : 640.0;  // 10 windows
    const SingleSourceResult r = geodesic(in, s, f);
    EXPECT_FALSE(r.exact);
    ASSERT_EQ(r.length.size(), in.positions.rows());
    ASSERT_EQ(r.paths.size(), static_cast<std::size_t>(in.positions.rows()));
    Index straight = 0;
    for (Index v = 0; v < in.positions.rows(); ++v) {
      EXPECT_GE(r.length[v], e.length[v] - 1e-9) << v;
      straight += std::abs(r.length[v] - e.length[v]) <= 1e-9;
    }
    EXPECT_GE(straight, in.positions.rows() - r.blocked);
    EXPECT_GE(straight, 0.9 * double(in.positions.rows()));
    EXPECT_EQ(r.paths[static_cast<std::size_t>(s)].size(), 1u);
  }
}

TEST(RecipeGeodesic, BadCurvesAndOptionsRejected) {
  const io::SurfaceInput in = flat_grid();
  GivenCurve c;
  c.origin = "FILE:3";
  c.points = {at_vertex(0), at_vertex(81)};
  try {
    geodesic(in, {c});
    ADD_FAILURE() << "vertex 81 of 81 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("FILE:3: vertex 81 out of range [0, 81)"),
              std::string::npos)
        << e.what();
  }
  c.points = {at_vertex(0), at_vertex(0)};
  EXPECT_THROW(geodesic(in, {c}), InvalidInput);
  EXPECT_THROW(geodesic(in, Index{81}), InvalidInput);
  GeodesicOptions bezier;
  bezier.bezier_rounds = 2;
  c.points = {at_vertex(0), at_vertex(40), at_vertex(80)};
  c.closed = true;
  EXPECT_THROW(geodesic(in, {c}, bezier), InvalidInput);  // a Bézier curve is open
  io::SurfaceInput cloud;
  cloud.positions = in.positions;
  EXPECT_THROW(geodesic(cloud, Index{0}), InvalidInput);
}

TEST(OptionsValidate, RecipeOptions) {
  GeodesicOptions{}.validate();
  test::expect_each_rejected(&GeodesicOptions::mollify_relative_epsilon, {-1.0, 2.0, kNan},
                             "mollify_relative_epsilon");
  GeodesicOptions g;
  g.bezier_rounds = 17;
  test::expect_rejected(g, "bezier_rounds");
  solvers::DistanceOptions{}.validate();
  solvers::DistanceOptions d;
  d.time_factor = 0.0;
  test::expect_rejected(d, "time_factor");
  d = {};
  d.correction_steps = -1;
  test::expect_rejected(d, "correction_steps");
  solvers::FieldOptions{}.validate();
  test::expect_each_rejected(&solvers::FieldOptions::symmetry, {0, -4}, "symmetry");
  solvers::FieldOptions f;
  f.intrinsic_constraints = {{3, kNan}};
  test::expect_rejected(f, "intrinsic_constraints[0]");
  solvers::CurveSurfaceOptions{}.validate();
  test::expect_each_rejected(&solvers::CurveSurfaceOptions::mollify_relative_epsilon, {-1.0, kNan},
                             "mollify_relative_epsilon");
  solvers::CurveSurfaceOptions cs;
  cs.refine = solvers::SurfaceRefineOptions{};
  cs.refine->min_angle_degrees = 40;
  test::expect_rejected(cs, "minimum angle");
  solvers::RefinedDistanceOptions{}.validate();
  test::expect_each_rejected(&solvers::RefinedDistanceOptions::resolution, {0.0, kNan},
                             "resolution");
  test::expect_each_rejected(&solvers::RefinedDistanceOptions::time_factor, {-1.0}, "time_factor");
  test::expect_each_rejected(&solvers::RefinedDistanceOptions::correction_steps, {-1},
                             "correction_steps");
}

TEST(RecipeNames, ForwardToTheSolvers) {
  const io::SurfaceInput in = flat_grid();
  const solvers::PreparedSurface s = solvers::prepare_surface(in);
  const Index src = vertex_at(in, 0.5, 0.5);
  EXPECT_EQ(distance(s, {src}), solvers::geodesic_distance(s, {src}));
  const Laplacian l = laplacian(s);
  EXPECT_LT((l.L * Eigen::VectorXd::Ones(l.L.cols())).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(l.mass.sum(), 1.0, 1e-12);  // the unit square's area
  const Eigen::MatrixX2d uv = logmap(s, src);
  EXPECT_EQ(uv, solvers::log_map_on(s, solvers::vector_heat_solver(s), src));
  EXPECT_EQ(uv.row(src).norm(), 0.0);
}

}  // namespace
}  // namespace ifem::recipes

namespace ifem::recipes {
namespace {

// The one tokenizer of comma lists and point tokens: empty fields are kept, so "0,,1" is three
// fields (the caller then names the empty one) and a trailing comma is an empty last field.
TEST(RecipesTextFormats, SplitFieldsKeepsEmptyFields) {
  EXPECT_EQ(split_fields("0,1,2", ','), (std::vector<std::string>{"0", "1", "2"}));
  EXPECT_EQ(split_fields("0,,1", ','), (std::vector<std::string>{"0", "", "1"}));
  EXPECT_EQ(split_fields("0,1,", ','), (std::vector<std::string>{"0", "1", ""}));
  EXPECT_EQ(split_fields("", ','), (std::vector<std::string>{""}));
  EXPECT_EQ(split_fields("face:3:0.25:0.5", ':'),
            (std::vector<std::string>{"face", "3", "0.25", "0.5"}));
}

}  // namespace
}  // namespace ifem::recipes
