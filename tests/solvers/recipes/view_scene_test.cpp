// `ifem view`'s scene (solvers/recipes/view_scene.h): the intrinsic edges traced over the input
// (one polyline per intrinsic edge, every point on an input face, after flips and after
// insertions), the glyphs of an N-direction field (tangent, turned by 2π/N), the OBJ polyline
// reader's lines and errors, and the page (markers filled, data escaped, three.js inlined).
#include "solvers/recipes/view_scene.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/refine/signpost.h"
#include "solvers/recipes/render.h"
#include "solvers/test_util.h"

namespace ifem::recipes {
namespace {

using Vec = Eigen::Vector3d;

// Distance from p to triangle abc (closest point by regions, Ericson's "Real-Time Collision
// Detection" §5.1.5).
double point_triangle_distance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  }
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * vb * denom + ac * vc * denom)).norm();
}

double distance_to_mesh(const Vec& p, const intrinsic::TriangleMesh& m) {
  double best = INFINITY;
  for (const Triangle& t : m.faces) {
    best = std::min(best, point_triangle_distance(p, m.positions.row(t[0]), m.positions.row(t[1]),
                                                  m.positions.row(t[2])));
  }
  return best;
}

// Every intrinsic edge is one polyline from its tail to its head, every point on the input.
void expect_traced_edges(const intrinsic::TriangleMesh& m,
                         const intrinsic::SignpostTriangulation& st) {
  Scene scene = view_scene(test::as_input(m), "t");
  add_intrinsic_edges(scene, st);
  const auto& tri = st.intrinsic();
  ASSERT_EQ(scene.intrinsic_edges.size(), std::size_t(tri.n_edges()));
  const Positions where = st.vertex_positions();
  for (Index e = 0; e < tri.n_edges(); ++e) {
    const auto& line = scene.intrinsic_edges[e];
    ASSERT_GE(line.size(), 2u);
    const Index h = tri.edge_halfedge(e);
    const Vec a = where.row(tri.tail(h)), b = where.row(tri.head(h));
    const bool forward = (line.front() - a).norm() < 1e-9;
    EXPECT_LT(((forward ? line.front() : line.back()) - a).norm(), 1e-9) << "edge " << e;
    EXPECT_LT(((forward ? line.back() : line.front()) - b).norm(), 1e-9) << "edge " << e;
    for (const Vec& p : line) ASSERT_LE(distance_to_mesh(p, m), 1e-9) << "edge " << e;
  }
}

// A sheared, bent grid (cells of both diagonals: half of them long ones, not Delaunay):
// flipping to intrinsic Delaunay bends edges over the input's, and the traces must still lie
// on it.
intrinsic::TriangleMesh sheared_grid(int n) {
  intrinsic::TriangleMesh m = intrinsic::grid(n, n);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v) {
    const double x = m.positions(v, 0), y = m.positions(v, 1);
    m.positions.row(v) = Vec(x + 0.7 * y, y, 0.2 * std::sin(3 * x) * std::cos(2 * y));
  }
  return m;
}

TEST(ViewScene, IntrinsicEdgesAfterFlipsLieOnTheInput) {
  for (const int n : {5, 8}) {
    const intrinsic::TriangleMesh m = sheared_grid(n);
    intrinsic::SignpostTriangulation st(m.faces, m.positions);
    ASSERT_GT(st.flip_to_delaunay().flips, 0u) << n;
    expect_traced_edges(m, st);
  }
}

TEST(ViewScene, IntrinsicEdgesAfterInsertionsLieOnTheInput) {
  const intrinsic::TriangleMesh m = sheared_grid(6);
  intrinsic::SignpostTriangulation st(m.faces, m.positions);
  st.flip_to_delaunay();
  for (Index f = 0; f < 40; f += 7) st.insert_vertex(f, Vec(0.2, 0.3, 0.5));
  st.split_edge(3, 0.4);
  st.flip_to_delaunay();
  ASSERT_GT(st.intrinsic().n_vertices(), Index(m.positions.rows()));
  expect_traced_edges(m, st);
}

// Pixels of the intrinsic edges' colour (blue well above red) in a render of the scene.
long blue_pixels(const Scene& scene) {
  solvers::RenderOptions o;
  o.width = 320;
  o.height = 240;
  const solvers::Image img = solvers::render_scene(render_scene_of(scene), o).image;
  long n = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const auto p = img.pixel(x, y);
      n += p[2] > p[0] + 60 && p[2] > p[1] + 30;
    }
  }
  return n;
}

TEST(ViewScene, RenderDrawsTheIntrinsicEdgesThePageShows) {
  const intrinsic::TriangleMesh m = sheared_grid(8);
  Scene scene = view_scene(test::as_input(m), "t");
  EXPECT_EQ(blue_pixels(scene), 0);  // a grey surface on white: nothing blue
  intrinsic::SignpostTriangulation st(m.faces, m.positions);
  ASSERT_GT(st.flip_to_delaunay().flips, 0u);
  add_intrinsic_edges(scene, st);
  const solvers::RenderScene r = render_scene_of(scene);
  EXPECT_EQ(r.intrinsic_edges, scene.intrinsic_edges);
  const long flipped = blue_pixels(scene);
  EXPECT_GT(flipped, 1000);
  // more intrinsic edges (inserted vertices: three more edges each) draw more blue pixels
  for (Index f = 0; f < 90; f += 3) st.insert_vertex(f, Vec(0.3, 0.3, 0.4));
  st.flip_to_delaunay();
  ASSERT_GT(st.intrinsic().n_edges(), Index(scene.intrinsic_edges.size()) + 60);
  scene.intrinsic_edges.clear();
  add_intrinsic_edges(scene, st);
  EXPECT_GT(blue_pixels(scene), flipped + flipped / 10);
}

TEST(ViewScene, RenderSceneTakesTheNamedFieldCurvesAndGlyphs) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(1);
  Scene scene = view_scene(test::as_input(m), "t");
  EXPECT_EQ(render_scene_of(scene).field.size(), 0);  // no field: a grey surface
  add_field(scene, {"x", "", m.positions.col(0)});
  add_field(scene, {"y", "", m.positions.col(1)});
  add_polylines(scene, "a", {{Vec(0, 0, 1), Vec(1, 0, 0)}});
  add_polylines(scene, "b", {{Vec(0, 1, 0), Vec(1, 0, 0), Vec(0, 0, 1)}});
  scene.glyph_segments.resize(4, 3);
  scene.glyph_segments << 0, 0, 1, 0.1, 0, 1, 1, 0, 0, 1, 0.1, 0;
  solvers::RenderScene r = render_scene_of(scene);
  EXPECT_EQ(r.field_name, "x");  // the first field by default
  EXPECT_EQ(r.field, m.positions.col(0));
  r = render_scene_of(scene, "y");
  EXPECT_EQ(r.field, m.positions.col(1));
  ASSERT_EQ(r.curves.size(), 2u);  // every group's polylines
  EXPECT_EQ(r.curves[1].size(), 3u);
  ASSERT_EQ(r.glyphs.size(), 2u);
  EXPECT_EQ(r.glyphs[1][1], Vec(1, 0.1, 0));
  try {
    render_scene_of(scene, "z");
    ADD_FAILURE() << "an unknown property was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("x, y"), std::string::npos) << e.what();
  }
}

TEST(ViewScene, IntrinsicEdgesOfAnotherMeshAreRefused) {
  const intrinsic::TriangleMesh m = intrinsic::uv_sphere(6, 12), other = intrinsic::icosphere(2);
  Scene scene = view_scene(test::as_input(m), "t");
  EXPECT_THROW(
      add_intrinsic_edges(scene, intrinsic::SignpostTriangulation(other.faces, other.positions)),
      InvalidInput);
  intrinsic::TriangleMesh moved = m;
  moved.positions(5, 0) += 1e-6;
  EXPECT_THROW(
      add_intrinsic_edges(scene, intrinsic::SignpostTriangulation(moved.faces, moved.positions)),
      InvalidInput);
}

// On the unit icosphere (normal = position), N glyphs per vertex: tangent, of one length, the
// k-th turned by 2πk/N from the given vector; `singularity` marks its nonzero vertices.
TEST(ViewScene, GlyphsOfAnNDirectionField) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(3);
  const Eigen::Index n = m.positions.rows();
  Eigen::VectorXd fx(n), fy(n), fz(n), sing = Eigen::VectorXd::Zero(n);
  for (Eigen::Index v = 0; v < n; ++v) {
    Vec t = Vec::UnitZ().cross(Vec(m.positions.row(v)));
    if (t.norm() < 1e-3) t = Vec::UnitX();
    fx[v] = t.x(), fy[v] = t.y(), fz[v] = t.z();
  }
  sing[0] = 0.25, sing[7] = -0.25;
  for (const int symmetry : {1, 2, 4}) {
    Scene s = view_scene(test::as_input(m), "t");
    add_properties(s, {{"fx", fx}, {"fy", fy}, {"fz", fz}, {"singularity", sing}}, "", symmetry);
    ASSERT_EQ(s.glyph_segments.rows(), 2 * symmetry * n);
    ASSERT_EQ(s.singularities.size(), 2u);
    EXPECT_EQ(s.singularities[1].index, -0.25);
    EXPECT_EQ(s.fields.size(), 4u);
    const double length = (s.glyph_segments.row(1) - s.glyph_segments.row(0)).norm();
    for (Eigen::Index v = 0; v < n; ++v) {
      const Vec p = m.positions.row(v), normal = p.normalized();
      for (int k = 0; k < symmetry; ++k) {
        const Eigen::Index row = 2 * (symmetry * v + k);
        ASSERT_LT((Vec(s.glyph_segments.row(row)) - p).norm(), 1e-12);
        const Vec d = s.glyph_segments.row(row + 1) - s.glyph_segments.row(row);
        ASSERT_NEAR(d.norm(), length, 1e-12);
        EXPECT_LT(std::abs(d.dot(normal)), 0.05 * length) << v;  // area-weighted normal ≈ p
        const Vec first = s.glyph_segments.row(2 * symmetry * v + 1).transpose() - p;
        EXPECT_NEAR(d.dot(first) / (length * length), std::cos(2 * M_PI * k / symmetry), 0.01);
      }
    }
  }
  Scene s = view_scene(test::as_input(m), "t");
  EXPECT_THROW(add_properties(s, {{"fx", fx}}, "", 7), InvalidInput);
  EXPECT_THROW(add_properties(s, {{"short", Eigen::VectorXd::Zero(n - 1)}}), InvalidInput);
  add_field(s, {"a", "", fx});
  add_field(s, {"a", "", fy});
  EXPECT_EQ(s.fields[1].name, "a (2)");
}

class ViewFiles : public ::testing::Test {
 protected:
  std::filesystem::path dir_ =
      std::filesystem::temp_directory_path() /
      ("ifem_view_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream((dir_ / name).string()) << text;
    return (dir_ / name).string();
  }
};

TEST_F(ViewFiles, ObjPolylines) {  // the one OBJ polyline reader, as view and render use it
  const Polylines lines = solvers::read_polylines_obj(
      write("c.obj", "# curves\nv 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3 1\nvn 0 0 1\nl -1 -2\n"));
  ASSERT_EQ(lines.size(), 2u);
  ASSERT_EQ(lines[0].size(), 4u);
  EXPECT_EQ(lines[0][2], Vec(1, 1, 0));
  EXPECT_EQ(lines[0][3], Vec(0, 0, 0));
  EXPECT_EQ(lines[1][0], Vec(1, 1, 0));
  EXPECT_EQ(lines[1][1], Vec(1, 0, 0));
  for (const char* bad :
       {"v 0 0\nl 1 1\n", "v 0 0 0\nl 1 2\n", "v 0 0 0\nl 1 x\n", "v 0 0 nan\n"}) {
    try {
      solvers::read_polylines_obj(write("bad.obj", bad));
      ADD_FAILURE() << bad;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.obj, line"), std::string::npos) << e.what();
    }
  }
}

TEST_F(ViewFiles, PageHasEveryPartInlinedAndEscaped) {
  std::filesystem::create_directories(dir_ / "three/build");
  std::filesystem::create_directories(dir_ / "three/examples/jsm/controls");
  write("three/build/three.module.min.js", "export const MARK = 1;");
  write("three/examples/jsm/controls/OrbitControls.js", "export const ORBIT = 2;");
  const std::string three = (dir_ / "three").string();
  EXPECT_EQ(find_three_js(three), three);
  EXPECT_THROW(find_three_js((dir_ / "none").string()), IoError);

  const intrinsic::TriangleMesh m = intrinsic::icosphere(1);
  Scene s = view_scene(test::as_input(m), "a </script> & <b>");
  add_field(s, {"h</script>", "m", Eigen::VectorXd::LinSpaced(m.positions.rows(), -1.0, 1.0)});
  add_polylines(s, "c", {{Vec(0, 0, 1), Vec(1, 0, 0)}, {Vec(0, 0, 1)}});
  ASSERT_EQ(s.curves[0].lines.size(), 1u);  // the one-point polyline is dropped
  const std::string page = view_page(s, three);
  for (const char* marker : {"IFEM_THREE_URL", "IFEM_ORBIT_URL", "IFEM_TITLE", "IFEM_SCENE"}) {
    EXPECT_EQ(page.find(marker), std::string::npos) << marker;
  }
  // base64 of the two module texts, as data URLs
  EXPECT_NE(page.find("data:text/javascript;base64,ZXhwb3J0IGNvbnN0IE1BUksgPSAxOw=="),
            std::string::npos);
  EXPECT_NE(page.find("data:text/javascript;base64,ZXhwb3J0IGNvbnN0IE9SQklUID0gMjs="),
            std::string::npos);
  EXPECT_NE(page.find("<title>a &lt;/script&gt; &amp; &lt;b&gt;</title>"), std::string::npos);
  EXPECT_NE(page.find("\"name\":\"h\\u003c/script>\""), std::string::npos);
  EXPECT_EQ(page.find("h</script>"), std::string::npos);
  EXPECT_NE(page.find("\"units\":\"m\",\"min\":-1,\"max\":1,"), std::string::npos);
}

}  // namespace
}  // namespace ifem::recipes
