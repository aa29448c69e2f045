// Tests for the readers' polygon triangulation (intrinsic/io/polygons.cpp): no diagonal may
// coincide with an existing edge, so a manifold polygon mesh stays edge-manifold; area and
// orientation are kept; a polygon of millions of corners is read in linear time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "helpers.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/surface/build_surface.h"
#include "intrinsic/surface/face_analysis.h"

namespace ifem::io {
namespace {

namespace fs = std::filesystem;
using Polygon = std::vector<Index>;

fs::path write_temp(const std::string& name, const std::string& text) {
  const fs::path p =
      fs::temp_directory_path() / ("ifem_polygon_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::string obj_text(const std::vector<Eigen::Vector3d>& x, const std::vector<Polygon>& polys) {
  std::string s;
  for (const auto& p : x) {
    s += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) +
         "\n";
  }
  for (const auto& f : polys) {
    s += "f";
    for (Index v : f) s += " " + std::to_string(v + 1);
    s += "\n";
  }
  return s;
}

std::string off_text(const std::vector<Eigen::Vector3d>& x, const std::vector<Polygon>& polys) {
  std::string s = "OFF\n" + std::to_string(x.size()) + " " + std::to_string(polys.size()) + " 0\n";
  for (const auto& p : x) {
    s += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  }
  for (const auto& f : polys) {
    s += std::to_string(f.size());
    for (Index v : f) s += " " + std::to_string(v);
    s += "\n";
  }
  return s;
}

/// Reads the text as `name` (the extension picks the format) and removes the file.
SurfaceInput read_text(const std::string& name, const std::string& text) {
  const fs::path p = write_temp(name, text);
  SurfaceInput s = read_surface(p.string());
  fs::remove(p);
  return s;
}

/// The first-corner fan every reader produced before: (v0, vk, vk+1).
std::vector<Triangle> old_fan(const std::vector<Polygon>& polys) {
  std::vector<Triangle> t;
  for (const auto& f : polys) {
    for (std::size_t k = 1; k + 1 < f.size(); ++k) t.push_back({f[0], f[k], f[k + 1]});
  }
  return t;
}

Eigen::Vector3d area_vector(const Positions& x, const Polygon& f) {
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < f.size(); ++i) {
    a += 0.5 * Eigen::Vector3d(x.row(f[i])).cross(Eigen::Vector3d(x.row(f[(i + 1) % f.size()])));
  }
  return a;
}

/// Checks that each polygon's triangles use only its corners, keep its orientation and add up
/// to its (planar) area, and that the whole triangulation is edge-manifold.
void expect_faithful(const SurfaceInput& s, const std::vector<Polygon>& polys) {
  ASSERT_EQ(s.n_polygons, static_cast<Index>(polys.size()));
  ASSERT_EQ(s.triangles.size(), s.triangle_polygon.size());
  std::vector<Eigen::Vector3d> sum(polys.size(), Eigen::Vector3d::Zero());
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const Polygon& f = polys[s.triangle_polygon[t]];
    for (Index v : s.triangles[t]) EXPECT_NE(std::find(f.begin(), f.end(), v), f.end());
    const Polygon tri(s.triangles[t].begin(), s.triangles[t].end());
    const Eigen::Vector3d a = area_vector(s.positions, tri);
    EXPECT_GT(a.dot(area_vector(s.positions, f)), 0) << "triangle " << t << " flipped";
    sum[s.triangle_polygon[t]] += a;
  }
  for (std::size_t p = 0; p < polys.size(); ++p) {
    EXPECT_NEAR((sum[p] - area_vector(s.positions, polys[p])).norm(), 0, 1e-12) << p;
  }
  EXPECT_EQ(intrinsic::analyze_faces(s.triangles, s.positions.rows()).nonmanifold_edges, 0);
}

// Two non-planar quads Q1 = (a,b,c,d) and Q2 = (c,b,a,e) share the two consecutive sides a–b
// and b–c; a third quad (c,e,a,d) closes them into a sphere (5 vertices, 6 edges, 3 faces).
// The old fan from each first corner cuts Q1 along a–c, Q2 along c–a (repeating the triangle
// a,b,c) and Q3 along c–a again: a–c gets 6 faces, so the mesh went to the tufted cover and
// refinement was refused. Here a–c is the shortest diagonal of all three, so only collision
// avoidance makes Q2 and Q3 take b–e and e–d.
TEST(PolygonTriangulation, QuadsSharingTwoSidesStayManifold) {
  const std::vector<Eigen::Vector3d> x = {
      {-0.5, 0, 0}, {0, 0, 1}, {0.5, 0, 0}, {0, -1, 0.3}, {0, 1, 0.3}};  // a b c d e
  const std::vector<Polygon> polys = {{0, 1, 2, 3}, {2, 1, 0, 4}, {2, 4, 0, 3}};
  EXPECT_GT(intrinsic::analyze_faces(old_fan(polys), 5).nonmanifold_edges, 0);
  for (const auto& [name, text] : {std::pair{std::string("pillow.obj"), obj_text(x, polys)},
                                   std::pair{std::string("pillow.off"), off_text(x, polys)}}) {
    SCOPED_TRACE(name);
    const SurfaceInput s = read_text(name, text);
    EXPECT_EQ(s.n_non_triangles, 3);
    EXPECT_EQ(s.triangle_polygon, (std::vector<Index>{0, 0, 1, 1, 2, 2}));
    EXPECT_EQ(s.triangles[0], (Triangle{0, 1, 2}));  // Q1: the shorter diagonal a–c
    const auto stats = intrinsic::analyze_faces(s.triangles, s.positions.rows());
    EXPECT_EQ(stats.nonmanifold_edges, 0);
    EXPECT_EQ(stats.edges, 9);
    EXPECT_EQ(stats.boundary_edges, 0);
    const auto surface = intrinsic::build_surface(s.triangles, s.positions);
    EXPECT_EQ(surface.path, intrinsic::SurfacePath::kManifold) << surface.reason_detail;
  }
}

TEST(PolygonTriangulation, CubeAndHexagonalPrism) {
  std::vector<Eigen::Vector3d> cube;
  for (int i = 0; i < 8; ++i) cube.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const std::vector<Polygon> cube_faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Eigen::Vector3d> prism;
  for (int z = 0; z < 2; ++z) {
    for (int k = 0; k < 6; ++k) {
      const double t = k * M_PI / 3;
      prism.emplace_back(std::cos(t), std::sin(t), 2.0 * z);
    }
  }
  std::vector<Polygon> prism_faces = {{5, 4, 3, 2, 1, 0}, {6, 7, 8, 9, 10, 11}};
  for (Index k = 0; k < 6; ++k) prism_faces.push_back({k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k});
  for (const auto& [x, polys] : {std::pair{cube, cube_faces}, std::pair{prism, prism_faces}}) {
    for (const std::string ext : {".obj", ".off"}) {
      SCOPED_TRACE(std::to_string(x.size()) + ext);
      const SurfaceInput s =
          read_text("solid" + ext, ext == ".obj" ? obj_text(x, polys) : off_text(x, polys));
      expect_faithful(s, polys);
      EXPECT_EQ(intrinsic::build_surface(s.triangles, s.positions).path,
                intrinsic::SurfacePath::kManifold);
    }
  }
}

/// The file's polygons as the sink collected them (before triangulate_polygons): each one's
/// run of fan triangles (v0, vk, vk+1) gives back its corners.
std::vector<Polygon> file_polygons(const fs::path& file) {
  const std::string ext = file_extension(file.string());
  const std::string bytes = detail::read_file(file.string());
  SurfaceInput raw;
  if (ext == ".obj") raw = detail::read_obj(file.string(), bytes);
  if (ext == ".off") raw = detail::read_off(file.string(), bytes);
  if (ext == ".ply") raw = detail::read_ply(file.string(), bytes);
  if (ext == ".stl") raw = detail::read_stl(file.string(), bytes);
  std::vector<Polygon> polys(static_cast<std::size_t>(raw.n_polygons));
  for (std::size_t t = 0; t < raw.triangles.size(); ++t) {
    Polygon& f = polys[raw.triangle_polygon[t]];
    if (f.empty()) f = {raw.triangles[t][0], raw.triangles[t][1]};
    f.push_back(raw.triangles[t][2]);
  }
  return polys;
}

std::uint64_t edge_key(Index a, Index b) {
  return (std::uint64_t(std::min(a, b)) << 32) | std::uint32_t(std::max(a, b));
}

// Every polygon mesh of the corpus: an edge of the triangulation has 3+ faces only when the
// polygons' own sides already meet there 3+ times, so each mesh keeps the path its polygons
// imply; and the triangles are faithful to their polygons.
TEST(PolygonTriangulation, CorpusPolygonMeshesGainNoNonmanifoldEdge) {
  IFEM_REQUIRE_SHARED_DATA();
  int polygon_meshes = 0;
  for (const auto& file : test::shared_files("meshes")) {
    if (test::skip_in_quick_run(file)) continue;
    const SurfaceInput s = read_surface(file.string());
    if (s.n_non_triangles == 0) continue;
    SCOPED_TRACE(file.filename().string());
    ++polygon_meshes;
    std::map<std::uint64_t, int> sides;
    for (const Polygon& f : file_polygons(file)) {
      for (std::size_t i = 0; i < f.size(); ++i) ++sides[edge_key(f[i], f[(i + 1) % f.size()])];
    }
    std::map<std::uint64_t, int> faces;
    for (const Triangle& t : s.triangles) {
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      for (int k = 0; k < 3; ++k) ++faces[edge_key(t[k], t[(k + 1) % 3])];
    }
    for (const auto& [edge, count] : faces) {
      if (count < 3) continue;
      const auto it = sides.find(edge);
      EXPECT_TRUE(it != sides.end() && it->second >= 3)
          << "edge (" << (edge >> 32) << "," << (edge & 0xffffffffu) << ") has " << count
          << " faces but the polygons' sides meet there " << (it == sides.end() ? 0 : it->second)
          << " times";
    }
  }
  EXPECT_GT(polygon_meshes, 0);
}

// One planar convex polygon of 2 million corners (points on a parabola, exact integers): read
// in linear time (the 120 s ctest timeout of this executable catches quadratic behaviour) into
// n − 2 triangles. The OBJ text is parsed from memory by the reader read_surface() uses.
TEST(PolygonTriangulation, TwoMillionCornerPolygonInLinearTime) {
  const std::int64_t n = 2000000;
  std::string text;
  text.reserve(static_cast<std::size_t>(n) * 40);
  for (std::int64_t i = 0; i < n; ++i) {
    text += "v " + std::to_string(i) + " " + std::to_string(i * i) + " 0\n";
  }
  text += "f";
  for (std::int64_t i = n; i >= 1; --i) text += " " + std::to_string(i);
  text += "\n";
  SurfaceInput s = detail::read_obj("long.obj", text);
  detail::triangulate_polygons(s);
  ASSERT_EQ(s.triangles.size(), static_cast<std::size_t>(n - 2));
  EXPECT_EQ(s.n_polygons, 1);
  EXPECT_EQ(s.n_non_triangles, 1);
  for (const Triangle& t : s.triangles) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
  }
  EXPECT_EQ(intrinsic::analyze_faces(s.triangles, s.positions.rows()).nonmanifold_edges, 0);
}

}  // namespace
}  // namespace ifem::io
