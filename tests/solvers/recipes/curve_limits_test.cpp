// Curves at the edges of what they can do (issue 30), at the library level: io::quoted_excerpt
// (every file error shows garbage escaped on one line), the Bézier estimate against what
// bezier_curve() inserts and the refusals of check_curve_budget(), FlipOut's iteration cap
// refused unless accepted (curves and the geodesic recipe), the constraints file (origins,
// empty file, conflicting directions), and curves on a triangle soup at the default settings.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/geodesic/curve_network.h"
#include "intrinsic/io/tokens.h"
#include "solvers/recipes/curves.h"
#include "solvers/recipes/geodesic.h"
#include "solvers/recipes/tangent_fields.h"
#include "solvers/recipes/text_formats.h"

namespace ifem {
namespace {

// Every byte of s printable ASCII or part of UTF-8 (no control byte, no DEL).
bool printable(const std::string& s) {
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) return false;
  }
  return true;
}

TEST(QuotedExcerpt, EscapesControlBytesKeepsUtf8AndTruncates) {
  using io::quoted_excerpt;
  EXPECT_EQ(quoted_excerpt("abc"), "'abc'");
  EXPECT_EQ(quoted_excerpt(std::string("a\0b", 3)), "'a\\0b'");
  EXPECT_EQ(quoted_excerpt("a\tb\r\n\\"), "'a\\tb\\r\\n\\\\'");
  EXPECT_EQ(quoted_excerpt("\x01\x1b\x7f"), "'\\x01\\x1b\\x7f'");
  EXPECT_EQ(quoted_excerpt("≥ é"), "'≥ é'");  // well-formed UTF-8 kept
  EXPECT_EQ(quoted_excerpt("\xff\xfe\xe2\x89"), "'\\xff\\xfe\\xe2\\x89'");  // malformed
  const std::string longer(100, 'x');
  EXPECT_EQ(quoted_excerpt(longer, 5), "'xxxxx'... (100 bytes)");
  EXPECT_EQ(quoted_excerpt(std::string(10, '\0'), 3), "'\\0\\0\\0'... (10 bytes)");
  std::string all;
  for (int c = 0; c < 256; ++c) all += static_cast<char>(c);
  EXPECT_TRUE(printable(quoted_excerpt(all, 1000)));
}

class FileErrors : public ::testing::Test {
 protected:
  std::string write(const std::string& bytes) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::filesystem::path p =
        std::filesystem::temp_directory_path() /
        ("ifem_limits_" + std::string(info->name()) + "_" + std::to_string(files_.size()) + ".txt");
    std::ofstream(p, std::ios::binary) << bytes;
    files_.push_back(p);
    return p.string();
  }
  void TearDown() override {
    for (const auto& p : files_) std::filesystem::remove(p);
  }
  // read(file) throws an Error whose message names FILE:line, has `expected`, and is printable
  // (the message's length is its string's: no NUL inside).
  template <class Read>
  void expect_clean_error(const std::string& bytes, int line, const std::string& expected,
                          Read read) {
    const std::string p = write(bytes);
    try {
      read(p);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(p + ":" + std::to_string(line) + ": "), std::string::npos) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what;
      EXPECT_TRUE(printable(what)) << what;
    }
  }

 private:
  std::vector<std::filesystem::path> files_;
};

std::string junk() { return std::string("\x00\x01\x1b[31m\rX\x7f\xff\n", 11); }

TEST_F(FileErrors, GarbageIsEscapedInEveryFormat) {
  expect_clean_error("0 1 " + junk(), 1, "'\\0\\x01\\x1b[31m' is not a vertex id",
                     solvers::read_curves_file);
  expect_clean_error("path 0 " + junk(), 1, "'\\0\\x01\\x1b[31m' is not a point",
                     [](const std::string& p) { return recipes::read_network_file(p, false); });
  expect_clean_error("1 " + junk(), 1, "got '1 \\0\\x01", recipes::read_constraints_file);
  expect_clean_error(junk(), 1, "got '\\0\\x01", recipes::read_vertex_list);
  expect_clean_error("0 1 2 " + std::string(5000, '\x80') + "\n", 1, "... (5000 bytes)",
                     solvers::read_curves_file);
}

TEST_F(FileErrors, ConstraintsFileOriginsEmptyAndConflicts) {
  const std::string p = write("2 1 0 0\n# x\n5 0 0.5 1\n");
  const std::vector<solvers::InputDirection> c = recipes::read_constraints_file(p);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].origin, p + ":1");
  EXPECT_EQ(c[1].origin, p + ":3");
  EXPECT_THROW(recipes::read_constraints_file(write("# none\n\n")), IoError);
  // on a flat grid: out of range and two different directions at one vertex, named by line
  const intrinsic::TriangleMesh m = intrinsic::grid(6, 6);
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  const solvers::PreparedSurface s = solvers::prepare_surface(in);
  solvers::FieldOptions o;
  o.constraints = recipes::read_constraints_file(write("5 1 0 0\n7 0 1 0\n5 0 1 0\n"));
  try {
    solvers::direction_field_on(s, o);
    ADD_FAILURE() << "two directions at vertex 5 accepted";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(o.constraints[2].origin + " (vertex 5): a second, different direction"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find(o.constraints[0].origin + " (vertex 5)"), std::string::npos) << what;
  }
  o.constraints = {{5, {1, 0, 0}, ""}, {5, {3, 0, 0}, ""}};  // the same direction: held
  EXPECT_EQ(solvers::direction_field_on(s, o).vectors.rows(), s.n_input_vertices());
  o.constraints = {{49, {1, 0, 0}, "F:9"}};
  try {
    solvers::direction_field_on(s, o);
    ADD_FAILURE() << "vertex 49 of 49 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("F:9 (vertex 49): vertex out of range"), std::string::npos)
        << e.what();
  }
}

// A flat 16×16 grid of the unit square (mean edge length about 1/16).
io::SurfaceInput flat_grid() {
  const intrinsic::TriangleMesh m = intrinsic::grid(16, 16);
  io::SurfaceInput in;
  in.positions = m.positions;
  in.triangles = m.faces;
  return in;
}

TEST(BezierBudget, EstimateBoundsTheInsertedVertices) {
  const io::SurfaceInput in = flat_grid();
  for (const std::vector<Index>& ctrl :
       std::vector<std::vector<Index>>{{18, 150, 270}, {18, 100, 200, 270}}) {
    for (const int rounds : {0, 1, 3}) {
      intrinsic::SignpostTriangulation st(in.triangles, in.positions);
      const intrinsic::CurveSpec spec{ctrl, intrinsic::CurveShape::kBezier, rounds};
      const intrinsic::CurveEstimate e = intrinsic::estimate_curves(st.intrinsic(), {spec});
      const double d = double(ctrl.size() - 1);
      EXPECT_EQ(e.added_vertices[0], d * (d + 1) / 2 * (std::ldexp(1.0, rounds) - 1.0));
      EXPECT_EQ(e.vertices, 289 + e.added_vertices[0]);
      const intrinsic::BezierCurve b = intrinsic::bezier_curve(st, ctrl, rounds);
      EXPECT_LE(b.inserted_vertices, e.added_vertices[0]);
      // on a grid a midpoint at round 1 may be a vertex already; later most are new
      if (rounds == 3) {
        EXPECT_GE(b.inserted_vertices, 0.8 * e.added_vertices[0]);
      }
      // the segment figure is generous: at least the final polygon's mean segment
      EXPECT_GE(e.segment_length[0] * (1 + 1e-12),
                b.report.final_length / double(b.controls.size() - 1));
    }
  }
}

TEST(BezierBudget, RefusedUpFrontWithTheRoundsThatFit) {
  const io::SurfaceInput in = flat_grid();
  solvers::CurveCondition c;
  c.vertices = {18, 150, 270};
  c.shape = intrinsic::CurveShape::kBezier;
  c.bezier_rounds = 16;
  c.values = {0.0};
  c.origin = "FILE:4";
  std::string fit;
  try {
    solvers::prepare_curve_surface(in, {c});
    ADD_FAILURE() << "16 rounds accepted";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("curve at FILE:4: a Bézier curve of degree 2 with 16 rounds adds up to "
                        "1.97e+05 vertices"),
              std::string::npos)
        << what;
    const std::size_t at = what.find("Use at most ");
    ASSERT_NE(at, std::string::npos) << what;
    fit = what.substr(at + 12, what.find(' ', at + 12) - at - 12);
  }
  c.bezier_rounds = std::stoi(fit);  // the rounds that fit complete
  EXPECT_GE(c.bezier_rounds, 3);
  const solvers::CurveSurface s = solvers::prepare_curve_surface(in, {c});
  EXPECT_GT(s.network.bezier_midpoints, 0);
  EXPECT_TRUE(solvers::curve_distance(s).allFinite());
  c.bezier_rounds = 2;  // a budget below the mesh itself
  solvers::CurveSurfaceOptions o;
  o.max_memory_bytes = 1e5;
  try {
    solvers::prepare_curve_surface(in, {c}, o);
    ADD_FAILURE() << "a 100 kB budget accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("above the memory budget of 0.0001 GB"), std::string::npos)
        << e.what();
  }
}

TEST(IterationCap, RefusedUnlessAccepted) {
  const io::SurfaceInput in = flat_grid();
  solvers::CurveCondition c;  // a path through a detour: FlipOut needs several reroutes
  c.vertices = {18, 280, 30};
  c.values = {0.0};
  c.origin = "FILE:1";
  solvers::CurveSurfaceOptions o;
  o.flipout.max_iterations = 1;
  try {
    solvers::prepare_curve_surface(in, {c}, o);
    ADD_FAILURE() << "a curve at the iteration cap accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("FlipOut stopped at its iteration cap (1 reroutes"),
              std::string::npos)
        << e.what();
  }
  o.accept_partial = true;
  EXPECT_EQ(solvers::prepare_curve_surface(in, {c}, o).network.flipout.stopped_by,
            intrinsic::FlipOutStop::kIterationCap);
  recipes::GivenCurve g;
  g.origin = "NET:2";
  for (const Index v : {18, 280, 30}) {
    recipes::GivenPoint p;
    p.vertex = v;
    p.token = std::to_string(v);
    g.points.push_back(p);
  }
  recipes::GeodesicOptions go;
  go.flipout.max_iterations = 1;
  EXPECT_THROW(recipes::geodesic(in, {g}, go), InvalidInput);
  go.accept_partial = true;
  EXPECT_EQ(recipes::geodesic(in, {g}, go).report.stopped_by,
            intrinsic::FlipOutStop::kIterationCap);
  go = {};
  EXPECT_NE(recipes::geodesic(in, {g}, go).report.stopped_by,
            intrinsic::FlipOutStop::kIterationCap);
}

// tests/data/soup_icosphere.obj: curves on piece 0 (vertices 0..~30), a lone triangle
// (240..242) and a zero-area face (243..245, mollified to a tiny triangle).
TEST(SoupCurves, DistanceAtDefaultAndOtherMollifications) {
  const io::SurfaceInput in = io::read_surface((test::test_data() / "soup_icosphere.obj").string());
  solvers::CurveCondition a, b;
  a.vertices = {0, 1};  // along the piece's boundary, past a reflex corner
  b.vertices = {5, 8, 13};
  for (const double eps : {1e-5, 1e-6, 1e-3}) {
    solvers::CurveSurfaceOptions o;
    o.mollify_relative_epsilon = eps;
    const solvers::CurveSurface s = solvers::prepare_curve_surface(in, {a, b}, o);
    const Eigen::VectorXd d = solvers::curve_distance(s);
    ASSERT_EQ(d.size(), 246);
    Index finite = 0;
    for (const Index v : {0, 1, 5, 8, 13}) EXPECT_EQ(d[v], 0.0) << eps;
    for (Eigen::Index v = 0; v < d.size(); ++v) {
      EXPECT_FALSE(std::isnan(d[v])) << v;
      if (!std::isfinite(d[v])) continue;
      ++finite;
      EXPECT_GE(d[v], 0.0);
      EXPECT_LT(d[v], 2.0);  // within a piece of the unit sphere
    }
    EXPECT_GE(finite, 20) << eps;  // piece 0, and nothing else
    EXPECT_LE(finite, 40) << eps;
    for (Index v = 240; v < 246; ++v) EXPECT_TRUE(std::isinf(d[v])) << v;
  }
  // the plain path on the same soup at the smaller margin (failed before, as the curve path)
  solvers::PrepareOptions po;
  po.mollify_relative_epsilon = 1e-7;
  const solvers::PreparedSurface p = solvers::prepare_surface(in, po);
  EXPECT_EQ(solvers::geodesic_distance(p, {0})[0], 0.0);
}

}  // namespace
}  // namespace ifem
