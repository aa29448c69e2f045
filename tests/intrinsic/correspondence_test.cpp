// The correspondence view and the saved triangulations: "ifem-integer 1" restores normal
// coordinates, roundabouts and spokes exactly (same common subdivision, same vertex locations),
// either format is told apart by load_triangulation(), bad files are refused with the file and
// what is wrong, and signposts and integer coordinates driven by the same refinement agree on
// everything the view gives.
#include "intrinsic/integer/correspondence.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/refine/delaunay_refine.h"

namespace ifem::intrinsic {
namespace {

std::string temp_file(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("ifem_correspondence_" + name)).string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

TriangleMesh mesh(int which) {
  // a grid of 1/8 × 1/3 cells (20° corners: refinement inserts), with boundary; an ellipsoid
  if (which == 0) return ifem::test::jittered(grid(8, 3), 0.01, 3);
  TriangleMesh m = ifem::test::jittered(icosphere(3), 0.05, 7);
  m.positions.col(0) *= 3.0;
  return m;
}

RefineOptions refine_to(double angle) {
  RefineOptions o;
  o.min_angle_degrees = angle;
  return o;
}

void expect_same(const CommonSubdivision& a, const CommonSubdivision& b) {
  ASSERT_EQ(a.positions.rows(), b.positions.rows());
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.intrinsic_face, b.intrinsic_face);
  EXPECT_EQ(a.input_face, b.input_face);
}

void expect_same(const std::vector<SurfacePoint>& a, const std::vector<SurfacePoint>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t v = 0; v < a.size(); ++v) {
    EXPECT_EQ(a[v].face, b[v].face) << "vertex " << v;
    EXPECT_EQ(a[v].bary, b[v].bary) << "vertex " << v;
  }
}

TEST(CorrespondenceSave, IntegerRoundTripIsExact) {
  for (int which : {0, 1}) {
    const TriangleMesh m = mesh(which);
    NormalCoordinateTriangulation nc(m.faces, m.positions, 1e-5);
    const RefineReport r = delaunay_refine(nc, refine_to(28.0));
    ASSERT_GT(r.insertions, 0);
    const std::string path = temp_file("round.ifem");
    CorrespondenceView(nc).save(path);
    const SavedTriangulation back = load_triangulation(path);
    ASSERT_TRUE(back.integer.has_value());
    ASSERT_FALSE(back.signposts.has_value());
    const NormalCoordinateTriangulation& b = *back.integer;
    EXPECT_EQ(b.intrinsic().tails(), nc.intrinsic().tails());
    EXPECT_EQ(b.intrinsic().twins(), nc.intrinsic().twins());
    EXPECT_EQ(b.intrinsic().lengths(), nc.intrinsic().lengths());
    EXPECT_EQ(b.input().lengths(), nc.input().lengths());
    EXPECT_EQ(b.input_face_origin(), nc.input_face_origin());
    for (Index e = 0; e < nc.intrinsic().n_edges(); ++e) {
      ASSERT_EQ(b.intrinsic().edge_halfedge(e), nc.intrinsic().edge_halfedge(e));
      ASSERT_EQ(b.normal_coordinate(e), nc.normal_coordinate(e)) << "edge " << e;
    }
    for (Index h = 0; h < nc.intrinsic().n_halfedges(); ++h) {
      ASSERT_EQ(b.roundabout(h), nc.roundabout(h)) << "halfedge " << h;
    }
    for (Index v = 0; v < nc.intrinsic().n_vertices(); ++v) {
      ASSERT_EQ(b.spokes(v).size(), nc.spokes(v).size()) << "vertex " << v;
    }
    expect_same(CorrespondenceView(b).common_subdivision(),
                CorrespondenceView(nc).common_subdivision());
    expect_same(CorrespondenceView(b).vertex_locations(),
                CorrespondenceView(nc).vertex_locations());
    // a second save of the restored object is the same file
    const std::string again = temp_file("again.ifem");
    CorrespondenceView(b).save(again);
    EXPECT_EQ(read_text(again), read_text(path));
    std::filesystem::remove(path);
    std::filesystem::remove(again);
  }
}

TEST(CorrespondenceSave, SignpostsRoundTripThroughTheSameLoader) {
  const TriangleMesh m = mesh(1);
  SignpostTriangulation st(m.faces, m.positions, 1e-5);
  delaunay_refine(st, refine_to(28.0));
  const std::string path = temp_file("signposts.ifem");
  CorrespondenceView(st).save(path);
  EXPECT_EQ(read_text(path).rfind(file_format(Correspondence::kSignposts), 0), 0u);
  const SavedTriangulation back = load_triangulation(path);
  ASSERT_TRUE(back.signposts.has_value());
  EXPECT_EQ(back.view().kind(), Correspondence::kSignposts);
  expect_same(back.view().vertex_locations(), CorrespondenceView(st).vertex_locations());
  expect_same(back.view().common_subdivision(), CorrespondenceView(st).common_subdivision());
  std::filesystem::remove(path);
}

// The IoError of loading `text` (as a file), or "" when it loads.
std::string load_error(const std::string& text) {
  const std::string path = temp_file("bad.ifem");
  write_text(path, text);
  try {
    (void)load_triangulation(path);
  } catch (const IoError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "";
}

TEST(CorrespondenceSave, BadFilesAreRefusedWithTheReason) {
  const TriangleMesh m = mesh(0);
  NormalCoordinateTriangulation nc(m.faces, m.positions);
  delaunay_refine(nc, refine_to(25.0));
  const std::string path = temp_file("good.ifem");
  nc.save(path);
  const std::string good = read_text(path);
  std::filesystem::remove(path);
  ASSERT_EQ(load_error(good), "");
  EXPECT_NE(load_error("hello\n").find("not a saved intrinsic triangulation"), std::string::npos);
  std::string v2 = good;
  v2.replace(0, std::string("ifem-integer 1").size(), "ifem-integer 2");
  EXPECT_NE(load_error(v2).find("unsupported version 2"), std::string::npos);
  EXPECT_NE(load_error(good.substr(0, good.size() / 2)).find(temp_file("bad.ifem")),
            std::string::npos);
  // a roundabout out of range: the last field of the first intrinsic halfedge record
  const std::size_t records = good.find("\nhalfedges\n");
  ASSERT_NE(records, std::string::npos);
  const std::size_t line = records + std::string("\nhalfedges\n").size();
  const std::size_t end = good.find('\n', line);
  std::string bad = good;
  bad.replace(good.rfind(' ', end) + 1, end - good.rfind(' ', end) - 1, "999");
  const std::string message = load_error(bad);
  EXPECT_NE(message.find("inconsistent normal coordinates"), std::string::npos) << message;
  EXPECT_NE(message.find("roundabout"), std::string::npos) << message;
  EXPECT_THROW(NormalCoordinateTriangulation::load(temp_file("missing.ifem")), IoError);
  EXPECT_THROW(parse_correspondence("signpost"), InvalidInput);
  EXPECT_EQ(parse_correspondence("integer"), Correspondence::kInteger);
}

TEST(CorrespondenceView, SignpostsAndIntegerAgree) {
  for (int which : {0, 1}) {
    const TriangleMesh m = mesh(which);
    SignpostTriangulation st(m.faces, m.positions, 1e-5);
    NormalCoordinateTriangulation nc(m.faces, m.positions, 1e-5);
    delaunay_refine(st, refine_to(28.0));
    ASSERT_GT(delaunay_refine(nc, refine_to(28.0)).insertions, 0);
    const CorrespondenceView a(st), b(nc);
    ASSERT_EQ(a.intrinsic().lengths(), b.intrinsic().lengths());
    const Positions pa = a.vertex_positions(), pb = b.vertex_positions();
    EXPECT_LT((pa - pb).cwiseAbs().maxCoeff(), 1e-9);
    Eigen::VectorXd f(a.n_input_vertices());
    for (Index v = 0; v < f.size(); ++v)
      f[v] = std::sin(3.0 * m.positions(v, 0)) + m.positions(v, 2);
    EXPECT_LT((a.input_to_intrinsic(f) - b.input_to_intrinsic(f)).cwiseAbs().maxCoeff(), 1e-9);
    const auto la = a.traced_edges_3d(), lb = b.traced_edges_3d();
    ASSERT_EQ(la.size(), lb.size());
    for (std::size_t e = 0; e < la.size(); ++e) {
      EXPECT_LT((la[e].front() - lb[e].front()).norm(), 1e-9);
      EXPECT_LT((la[e].back() - lb[e].back()).norm(), 1e-9);
    }
    const CommonSubdivision ca = a.common_subdivision(), cb = b.common_subdivision();
    std::set<std::pair<Index, Index>> pairs_a, pairs_b;
    for (std::size_t t = 0; t < ca.faces.size(); ++t)
      pairs_a.insert({ca.intrinsic_face[t], ca.input_face[t]});
    for (std::size_t t = 0; t < cb.faces.size(); ++t)
      pairs_b.insert({cb.intrinsic_face[t], cb.input_face[t]});
    EXPECT_EQ(pairs_a, pairs_b);  // the same polygons (intrinsic face ∩ input face)
  }
}

}  // namespace
}  // namespace ifem::intrinsic
