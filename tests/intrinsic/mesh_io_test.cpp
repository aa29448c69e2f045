// Tests for intrinsic/io/mesh_io.h: every format on small files written here with known contents,
// every kind of bad input (error type, file name and line / byte offset in the message),
// writer round trips, and the shared corpus against the vertex / face counts in its MANIFEST.
#include "intrinsic/io/mesh_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"
#include "intrinsic/core/errors.h"

namespace ifem::io {
namespace {

namespace fs = std::filesystem;

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("ifem_mesh_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

/// Runs f, which must throw IoError; the message must contain every part.
void expect_io_error(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no IoError thrown";
  } catch (const IoError& e) {
    const std::string what = e.what();
    for (const auto& part : parts) {
      EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
    }
  }
}

/// read_surface(path) must throw IoError naming the file (by its base name) and `where`.
void expect_read_error(const std::string& path, const std::string& where,
                       const std::string& problem = "") {
  std::vector<std::string> parts = {fs::path(path).filename().string(), where};
  if (!problem.empty()) parts.push_back(problem);
  expect_io_error([&] { read_surface(path); }, parts);
}

bool host_little_endian() {
  const std::uint16_t one = 1;
  unsigned char b = 0;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

/// Appends v in the given byte order.
template <class T>
void put(std::string& s, T v, bool big_endian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian == host_little_endian()) std::reverse(b, b + sizeof(T));
  s.append(reinterpret_cast<const char*>(b), sizeof(T));
}

std::vector<Triangle> tris(std::initializer_list<Triangle> t) { return t; }

// ---------------------------------------------------------------------------------- OBJ

TEST_F(MeshIo, ObjPolygonsTriangulatedAndExtrasIgnored) {
  const auto p = write("a.obj",
                       "# comment\n"
                       "mtllib a.mtl\n"
                       "o thing\n"
                       "g group\n"
                       "v 0 0 0\n"
                       "v 1 0 0   # trailing comment\n"
                       "v 1 1 0 1.0\n"
                       "v\t0 1 0\r\n"
                       "v 0.5 2 0\n"
                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                       "vn 0 0 1\n"
                       "usemtl stuff\n"
                       "s 1\n"
                       "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
                       "f 4//1 3//1 5//1\n"
                       "f 1/1 2/2 3/3 5/4 4\n"
                       "l 1 2\n");
  const SurfaceInput s = read_surface(p);
  EXPECT_EQ(s.format, "obj");
  ASSERT_EQ(s.positions.rows(), 5);
  EXPECT_EQ(s.positions(2, 1), 1.0);
  EXPECT_EQ(s.positions(4, 0), 0.5);
  // The square keeps the fan from its first corner (equal diagonals; 0–2 is no polygon's side).
  // The pentagon 0 1 2 4 3 may not reuse 0–2 (its fan would repeat triangle (0,1,2)): it takes
  // the diagonals 1–3 and 1–4 instead, same orientation and area.
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {0, 2, 3}, {3, 2, 4}, {3, 0, 1}, {1, 2, 4}, {1, 4, 3}}));
  EXPECT_EQ(s.triangle_polygon, (std::vector<Index>{0, 0, 1, 2, 2, 2}));
  EXPECT_EQ(s.n_polygons, 3);
  EXPECT_EQ(s.n_non_triangles, 2);
  EXPECT_EQ(s.normals.rows(), 0);
  EXPECT_TRUE(s.has_faces());
}

TEST_F(MeshIo, ObjNegativeIndicesAreRelative) {
  const auto p = write("neg.obj",
                       "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                       "f -3 -2 -1\n"
                       "v 1 1 0\n"
                       "f -3/-1/-1 -1 -2\n"
                       "f 1 -1 3\n");
  const SurfaceInput s = read_surface(p);
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {1, 3, 2}, {0, 3, 2}}));
}

TEST_F(MeshIo, ObjWithOnlyVerticesIsAPointCloud) {
  const auto p = write("cloud.obj", "v 0 0 0\nv 1 2 3\n");
  const SurfaceInput s = read_surface(p);
  EXPECT_EQ(s.positions.rows(), 2);
  EXPECT_FALSE(s.has_faces());
  EXPECT_EQ(s.n_polygons, 0);
  expect_io_error([&] { read_mesh(p); }, {"cloud.obj", "no faces"});
}

TEST_F(MeshIo, VertexOrderKeptWithUnreferencedAndDuplicateVertices) {
  // Vertex 1 is unreferenced, 3 duplicates 0: nothing is welded, dropped or reordered.
  const auto p = write("order.obj",
                       "v 5 0 0\nv 9 9 9\nv 0 5 0\nv 5 0 0\nv 0 0 5\n"
                       "f 5 4 3\n");
  const SurfaceInput s = read_surface(p);
  ASSERT_EQ(s.positions.rows(), 5);
  const double x[5] = {5, 9, 0, 5, 0};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(s.positions(i, 0), x[i]);
  EXPECT_EQ(s.triangles, tris({{4, 3, 2}}));
  EXPECT_EQ(s.welded_vertices, 0);

  const auto q = write("order.off", "OFF\n4 1 0\n1 0 0\n7 7 7\n0 1 0\n0 0 1\n3 3 2 0\n");
  const SurfaceInput t = read_surface(q);
  ASSERT_EQ(t.positions.rows(), 4);
  EXPECT_EQ(t.positions(1, 0), 7.0);
  EXPECT_EQ(t.triangles, tris({{3, 2, 0}}));
}

// ---------------------------------------------------------------------------------- OFF

TEST_F(MeshIo, OffHeadersCommentsAndColours) {
  const auto plain = write("plain.off",
                           "OFF\n# a comment\n\n4 2 0\n"
                           "0 0 0\n1 0 0\n1 1 0  # comment\n0 1 0\n"
                           "4 0 1 2 3 255 0 0\n3 0 2 3\n");
  SurfaceInput s = read_surface(plain);
  EXPECT_EQ(s.format, "off");
  EXPECT_EQ(s.positions.rows(), 4);
  // 0–2 is a side of the triangle 0 2 3, so the quad takes the other diagonal, 1–3 (the fan
  // from 0 would repeat the triangle (0,2,3)).
  EXPECT_EQ(s.triangles, tris({{1, 2, 3}, {0, 1, 3}, {0, 2, 3}}));
  EXPECT_EQ(s.n_polygons, 2);
  EXPECT_EQ(s.n_non_triangles, 1);

  const auto coff = write("c.off",
                          "COFF 3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 "
                          "255\n3 0 1 2 0.5 0.5 0.5 1\n");
  s = read_surface(coff);
  EXPECT_EQ(s.positions.rows(), 3);
  EXPECT_EQ(s.positions(1, 0), 1.0);
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}}));

  const auto noff = write("n.off", "NOFF\n3 1 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 1 0\n3 0 1 2\n");
  s = read_surface(noff);
  ASSERT_EQ(s.normals.rows(), 3);
  EXPECT_EQ(s.normals(2, 1), 1.0);
  EXPECT_EQ(s.normals(0, 2), 1.0);
}

// ---------------------------------------------------------------------------------- PLY

TEST_F(MeshIo, PlyAsciiExtraPropertiesNormalsAndSkippedElements) {
  const auto p = write("a.ply",
                       "ply\n"
                       "format ascii 1.0\n"
                       "comment hello\n"
                       "obj_info whatever\n"
                       "element vertex 4\n"
                       "property float x\n"
                       "property float y\n"
                       "property float z\n"
                       "property float nx\n"
                       "property float ny\n"
                       "property float nz\n"
                       "property double quality\n"
                       "property uchar red\n"
                       "element face 2\n"
                       "property list uchar int vertex_indices\n"
                       "property uchar flags\n"
                       "element edge 1\n"
                       "property int vertex1\n"
                       "property int vertex2\n"
                       "end_header\n"
                       "0 0 0 0 0 1 0.25 255\n"
                       "1 0 0 0 0 1 -1e300 0\n"
                       "1 1 0 0 0 1 3 7\n"
                       "0 1 0 0 0 1 4 8\n"
                       "4 0 1 2 3 9\n"
                       "3 3 2 1 0\n"
                       "0 1\n");
  const SurfaceInput s = read_surface(p);
  EXPECT_EQ(s.format, "ply-ascii");
  ASSERT_EQ(s.positions.rows(), 4);
  EXPECT_EQ(s.positions(2, 1), 1.0);
  ASSERT_EQ(s.normals.rows(), 4);
  EXPECT_EQ(s.normals(3, 2), 1.0);
  ASSERT_EQ(s.vertex_properties.size(), 2u);
  EXPECT_EQ(s.vertex_properties[0].name, "quality");
  EXPECT_EQ(s.vertex_properties[0].values[0], 0.25);
  EXPECT_EQ(s.vertex_properties[0].values[1], -1e300);
  EXPECT_EQ(s.vertex_properties[1].name, "red");
  EXPECT_EQ(s.vertex_properties[1].values[0], 255.0);
  EXPECT_EQ(s.vertex_properties[1].values[3], 8.0);
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
  EXPECT_EQ(s.n_polygons, 2);
  EXPECT_EQ(s.n_non_triangles, 1);
}

/// A binary PLY with assorted types, an element to skip before the faces, a face list with an
/// int count and short indices named vertex_index, and a trailing per-face property.
std::string binary_ply(bool big_endian) {
  std::string s = "ply\n";
  s += big_endian ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
  s += "element vertex 4\n"
       "property float x\n"
       "property double y\n"
       "property float z\n"
       "property short temperature\n"
       "property list uchar int ignored_list\n"
       "property ushort id\n"
       "element material 2\n"
       "property list ushort uchar name\n"
       "property float shininess\n"
       "element face 2\n"
       "property list int short vertex_index\n"
       "property float area\n"
       "end_header\n";
  const double xyz[4][3] = {{0, 0, 0}, {1, 0.1, 0}, {1, 1, 0.5}, {0, 1, -2}};
  for (int i = 0; i < 4; ++i) {
    put<float>(s, static_cast<float>(xyz[i][0]), big_endian);
    put<double>(s, xyz[i][1], big_endian);
    put<float>(s, static_cast<float>(xyz[i][2]), big_endian);
    put<std::int16_t>(s, static_cast<std::int16_t>(-100 * i), big_endian);
    put<std::uint8_t>(s, 2, big_endian);
    put<std::int32_t>(s, 7, big_endian);
    put<std::int32_t>(s, 8, big_endian);
    put<std::uint16_t>(s, static_cast<std::uint16_t>(60000 + i), big_endian);
  }
  for (int m = 0; m < 2; ++m) {
    put<std::uint16_t>(s, 3, big_endian);
    s += "abc";
    put<float>(s, 0.5f, big_endian);
  }
  put<std::int32_t>(s, 4, big_endian);
  for (std::int16_t v : {0, 1, 2, 3}) put<std::int16_t>(s, v, big_endian);
  put<float>(s, 1.0f, big_endian);
  put<std::int32_t>(s, 3, big_endian);
  for (std::int16_t v : {3, 2, 1}) put<std::int16_t>(s, v, big_endian);
  put<float>(s, 0.5f, big_endian);
  return s;
}

TEST_F(MeshIo, PlyBinaryLittleAndBigEndianAgree) {
  for (bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    const SurfaceInput s = read_surface(write(big ? "be.ply" : "le.ply", binary_ply(big)));
    EXPECT_EQ(s.format, big ? "ply-binary-be" : "ply-binary-le");
    ASSERT_EQ(s.positions.rows(), 4);
    EXPECT_EQ(s.positions(1, 1), 0.1);  // stored as double: exact
    EXPECT_EQ(s.positions(2, 2), 0.5);
    EXPECT_EQ(s.positions(3, 2), -2.0);
    EXPECT_EQ(s.normals.rows(), 0);
    ASSERT_EQ(s.vertex_properties.size(), 2u);
    EXPECT_EQ(s.vertex_properties[0].name, "temperature");
    EXPECT_EQ(s.vertex_properties[0].values[3], -300.0);
    EXPECT_EQ(s.vertex_properties[1].name, "id");
    EXPECT_EQ(s.vertex_properties[1].values[2], 60002.0);
    EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {0, 2, 3}, {3, 2, 1}}));
    EXPECT_EQ(s.triangle_polygon, (std::vector<Index>{0, 0, 1}));
  }
}

TEST_F(MeshIo, PlyTristripsDecoded) {
  // Strip 1: 0 1 2 2 3 4 → (0,1,2), degenerate connectors dropped, then (3,2,4) (odd: flipped).
  // Strip 2 after the -1 restart: 4 5 6 7 → (4,5,6), (6,5,7).
  const std::vector<int> strip = {0, 1, 2, 2, 3, 4, -1, 4, 5, 6, 7};
  const Triangle expected[4] = {{0, 1, 2}, {3, 2, 4}, {4, 5, 6}, {6, 5, 7}};
  std::string header =
      "element vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  std::string ascii = "ply\nformat ascii 1.0\n" + header;
  for (int i = 0; i < 8; ++i) ascii += std::to_string(i) + " " + std::to_string(i % 2) + " 0\n";
  ascii += std::to_string(strip.size());
  for (int v : strip) ascii += " " + std::to_string(v);
  ascii += "\n";
  std::string binary = "ply\nformat binary_big_endian 1.0\n" + header;
  for (int i = 0; i < 8; ++i) {
    put<float>(binary, static_cast<float>(i), true);
    put<float>(binary, static_cast<float>(i % 2), true);
    put<float>(binary, 0.0f, true);
  }
  put<std::int32_t>(binary, static_cast<std::int32_t>(strip.size()), true);
  for (int v : strip) put<std::int32_t>(binary, v, true);
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"sa.ply", ascii},
                                    std::pair<std::string, std::string>{"sb.ply", binary}}) {
    SCOPED_TRACE(name);
    const SurfaceInput s = read_surface(write(name, bytes));
    ASSERT_EQ(s.triangles.size(), 4u);
    for (int t = 0; t < 4; ++t) EXPECT_EQ(s.triangles[t], expected[t]);
    EXPECT_EQ(s.n_polygons, 4);
    EXPECT_EQ(s.positions.rows(), 8);
  }
}

TEST_F(MeshIo, TetWithSelfEdgeFromTestData) {
  const SurfaceInput s = read_mesh((test::test_data() / "tet_with_self_edge.ply").string());
  EXPECT_EQ(s.positions.rows(), 3);
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {0, 2, 1}}));
  EXPECT_FLOAT_EQ(static_cast<float>(s.positions(0, 0)), 1.359723f);
}

// ---------------------------------------------------------------------------------- STL

TEST_F(MeshIo, StlAsciiWeldsExactlyEqualCorners) {
  const auto p = write("sq.stl",
                       "solid square\n"
                       "  facet normal 0 0 1\n    outer loop\n"
                       "      vertex 0 0 0\n      vertex 1 0 0\n      vertex 1 1 0\n"
                       "    endloop\n  endfacet\n"
                       "  facet normal 0 0 1\n    outer loop\n"
                       "      vertex -0 0 0\n      vertex 1 1 0\n      vertex 0 1 0\n"
                       "    endloop\n  endfacet\n"
                       "endsolid square\n");
  const SurfaceInput s = read_surface(p);
  EXPECT_EQ(s.format, "stl-ascii");
  EXPECT_EQ(s.positions.rows(), 4);
  EXPECT_EQ(s.welded_vertices, 2);
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(s.positions(3, 1), 1.0);
}

std::string binary_stl(const std::string& header80, const std::vector<std::array<float, 9>>& t) {
  std::string s = header80;
  s.resize(80, ' ');
  put<std::uint32_t>(s, static_cast<std::uint32_t>(t.size()), false);
  for (const auto& tri : t) {
    for (int k = 0; k < 3; ++k) put<float>(s, 0.0f, false);
    for (float v : tri) put<float>(s, v, false);
    put<std::uint16_t>(s, 0, false);
  }
  return s;
}

TEST_F(MeshIo, StlBinaryStartingWithSolidIsDetected) {
  // A tetrahedron: 4 triangles, 12 corners, 4 distinct positions → 8 corners welded.
  const std::vector<std::array<float, 9>> tet = {{0, 0, 0, 0, 1, 0, 1, 0, 0},
                                                 {0, 0, 0, 0, 0, 1, 0, 1, 0},
                                                 {0, 0, 0, 1, 0, 0, 0, 0, 1},
                                                 {1, 0, 0, 0, 1, 0, 0, 0, 1}};
  const SurfaceInput s = read_surface(write("tet.stl", binary_stl("solid tet exported", tet)));
  EXPECT_EQ(s.format, "stl-binary");
  EXPECT_EQ(s.positions.rows(), 4);
  EXPECT_EQ(s.welded_vertices, 8);
  EXPECT_EQ(s.triangles, tris({{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {2, 1, 3}}));
  // Trailing bytes after the declared triangles: the size no longer matches, but the NUL bytes
  // still mark it as binary.
  const SurfaceInput t =
      read_surface(write("tail.stl", binary_stl("solid tet exported", tet) + "\n\n"));
  EXPECT_EQ(t.format, "stl-binary");
  EXPECT_EQ(t.triangles, s.triangles);
}

// ---------------------------------------------------------------------------------- XYZ

TEST_F(MeshIo, XyzWithAndWithoutNormals) {
  const SurfaceInput a =
      read_surface(write("n.xyz", "# points\n0 0 0 0 0 1\n\n1 2 3 1 0 0 # c\n-1e-3 4 5 0 1 0\n"));
  EXPECT_EQ(a.format, "xyz");
  ASSERT_EQ(a.positions.rows(), 3);
  EXPECT_EQ(a.positions(2, 0), -1e-3);
  ASSERT_EQ(a.normals.rows(), 3);
  EXPECT_EQ(a.normals(1, 0), 1.0);
  EXPECT_FALSE(a.has_faces());
  const SurfaceInput b = read_surface(write("p.TXT", "1 2 3\n4 5 6\n"));
  EXPECT_EQ(b.positions.rows(), 2);
  EXPECT_EQ(b.normals.rows(), 0);
  EXPECT_EQ(b.positions(1, 2), 6.0);
  expect_io_error([&] { read_mesh(path("p.TXT")); }, {"p.TXT", "no faces"});
}

// ---------------------------------------------------------------------------------- errors

TEST_F(MeshIo, MissingFileAndUnknownExtension) {
  expect_read_error(path("nope.obj"), "nope.obj", "no such file");
  expect_read_error(write("mesh.vtk", "x"), "mesh.vtk", "unknown extension");
  expect_read_error(write("noext", "x"), "noext", "unknown extension");
  expect_read_error(write("empty.obj", ""), "empty.obj", "no vertices");
  expect_read_error(write("comments.xyz", "# nothing\n"), "comments.xyz", "no vertices");
  expect_read_error(write("empty.ply", ""), "line 1", "not a PLY");
}

TEST_F(MeshIo, TextErrorsNameTheLine) {
  expect_read_error(write("m1.obj", "v 0 0 0\nv 1 0 0\nv 1 x3 0\n"), "line 3", "malformed");
  expect_read_error(write("m2.obj", "v 0 0 0\nv 1 0 0\nv 1 1e5x 0\n"), "line 3", "malformed");
  expect_read_error(write("m3.obj", "v 0 0 0\nv 1 0\n"), "line 2", "missing");
  expect_read_error(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "line 4", "index 0");
  expect_read_error(write("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"), "line 5",
                    "out of range");
  expect_read_error(write("rel.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"), "line 3",
                    "out of range");
  expect_read_error(write("tok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n"), "line 4",
                    "malformed");
  expect_read_error(write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), "line 3");
  expect_read_error(write("nan.obj", "v 0 0 0\nv nan 0 0\n"), "line 2", "NaN");
  expect_read_error(write("inf.obj", "v 0 0 0\nv 0 0 -inf\n"), "line 2", "NaN or infinite");
  expect_read_error(write("range.obj", "v 0 0 1e999\n"), "line 1", "out of range");

  expect_read_error(write("f.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "line 6",
                    "out of range");
  expect_read_error(write("h.off", "NOTOFF\n3 1 0\n"), "line 1", "header");
  expect_read_error(write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"), "line 4");
  expect_read_error(write("n.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 NaN\n3 0 1 2\n"), "line 5",
                    "NaN");
  expect_read_error(write("huge.off", "OFF\n4000000000 1 0\n0 0 0\n"), "line 2", "header");

  expect_read_error(write("c.xyz", "0 0 0\n1 1 1 0 0 1\n"), "line 2");
  expect_read_error(write("m.xyz", "0 0 0\n1 1 1\n2 2 2,\n"), "line 3", "malformed");
  expect_read_error(write("s.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
                    "line 4", "ends inside a facet");
  expect_read_error(write("s2.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n"),
                    "line 4", "missing");
}

const char* kPlyXyzHeader = "property float x\nproperty float y\nproperty float z\n";

TEST_F(MeshIo, PlyHeaderErrors) {
  expect_read_error(write("magic.ply", "plx\nformat ascii 1.0\n"), "line 1", "not a PLY");
  expect_read_error(write("noend.ply", std::string("ply\nformat ascii 1.0\nelement vertex 1\n") +
                                           kPlyXyzHeader + "0 0 0\n"),
                    "line 7", "end_header");
  expect_read_error(write("eof.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), "line 3",
                    "end_header");
  expect_read_error(write("type.ply",
                          "ply\nformat ascii 1.0\nelement vertex 1\nproperty "
                          "float128 x\nend_header\n0\n"),
                    "line 4", "unknown property type");
  expect_read_error(write("fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
                    "line 2", "format");
  expect_read_error(write("nox.ply",
                          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float "
                          "u\nend_header\n0\n"),
                    "line 3", "x, y and z");
  // A header that claims 4e9 vertices in a ~100-byte file fails fast instead of allocating.
  expect_read_error(write("huge_a.ply", std::string("ply\nformat ascii 1.0\nelement vertex "
                                                    "4000000000\n") +
                                            kPlyXyzHeader + "end_header\n0 0 0\n"),
                    "line 3", "4000000000");
  const std::string huge_b = std::string(
                                 "ply\nformat binary_little_endian 1.0\nelement vertex "
                                 "4000000000\n") +
                             kPlyXyzHeader + "end_header\n";
  expect_read_error(write("huge_b.ply", huge_b + std::string(12, '\0')),
                    "byte offset " + std::to_string(huge_b.size()), "4000000000");
  const std::string huge_f = std::string(
                                 "ply\nformat binary_little_endian 1.0\nelement vertex "
                                 "0\n") +
                             kPlyXyzHeader +
                             "element face 4000000000\nproperty list uchar int "
                             "vertex_indices\nend_header\n";
  expect_read_error(write("huge_f.ply", huge_f + std::string(12, '\0')), "byte offset",
                    "4000000000");
}

TEST_F(MeshIo, PlyBodyErrorsNameLineOrByteOffset) {
  const std::string header = std::string("element vertex 3\n") + kPlyXyzHeader +
                             "element face 1\nproperty list uchar int vertex_indices\n"
                             "end_header\n";
  // ASCII (the body starts on line 10): a malformed number on line 11, NaN on line 12, an
  // index out of range and a truncated face on line 13.
  const std::string a = "ply\nformat ascii 1.0\n" + header;
  expect_read_error(write("ra.ply", a + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "line 13",
                    "out of range");
  expect_read_error(write("ma.ply", a + "0 0 0\n1 0 0y\n0 1 0\n3 0 1 2\n"), "line 11", "malformed");
  expect_read_error(write("na.ply", a + "0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n"), "line 12", "NaN");
  expect_read_error(write("ta.ply", a + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"), "line 13", "truncated");
  // Binary little-endian: vertices take 36 bytes after the header.
  const std::string b = "ply\nformat binary_little_endian 1.0\n" + header;
  auto body = [&](float z2, std::int32_t last, bool truncate) {
    std::string s = b;
    const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, z2};
    for (float v : xyz) put<float>(s, v, false);
    put<std::uint8_t>(s, 3, false);
    put<std::int32_t>(s, 0, false);
    put<std::int32_t>(s, 1, false);
    if (!truncate) put<std::int32_t>(s, last, false);
    return s;
  };
  const std::size_t h = b.size();
  expect_read_error(write("rb.ply", body(0, 3, false)), "byte offset " + std::to_string(h + 36),
                    "out of range");
  expect_read_error(write("nb.ply", body(NAN, 2, false)), "byte offset " + std::to_string(h + 24),
                    "NaN");
  expect_read_error(write("tb.ply", body(0, 2, true)), "byte offset " + std::to_string(h + 36),
                    "truncated");
  expect_read_error(write("negb.ply", body(0, -7, false)), "byte offset " + std::to_string(h + 45),
                    "out of range");
}

TEST_F(MeshIo, StlBinaryErrors) {
  const std::vector<std::array<float, 9>> two = {{0, 0, 0, 1, 0, 0, 0, 1, 0},
                                                 {0, 0, 0, 0, 1, 0, 0, 0, 1}};
  std::string s = binary_stl("binary", two);
  expect_read_error(write("trunc.stl", s.substr(0, s.size() - 10)), "byte offset 134", "truncated");
  expect_read_error(write("short.stl", s.substr(0, 50)), "byte offset 50", "truncated");
  std::string huge = s.substr(0, 80);
  put<std::uint32_t>(huge, 4000000000u, false);
  expect_read_error(write("huge.stl", huge + std::string(16, '\0')), "byte offset 84",
                    "4000000000");
  auto bad = two;
  bad[1][4] = std::numeric_limits<float>::infinity();
  expect_read_error(write("inf.stl", binary_stl("binary", bad)),
                    "byte offset " + std::to_string(134 + 28), "NaN or infinite");
}

// ---------------------------------------------------------------------------------- writers

Positions random_positions(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Positions p(n, 3);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k)
      p(i, k) = u(rng) * std::pow(10.0, static_cast<int>(rng() % 40) - 20);
  }
  return p;
}

TEST_F(MeshIo, PlyRoundTripBinaryAndAscii) {
  const auto mesh = intrinsic::icosphere(3);
  const Index nv = static_cast<Index>(mesh.positions.rows());
  Positions positions = random_positions(nv, 7);
  positions(0, 0) = 0.1;
  positions(1, 1) = -0.0;
  positions(2, 2) = 5e-324;  // smallest subnormal
  std::vector<VertexProperty> props(2);
  props[0].name = "distance";
  props[0].values = Eigen::VectorXd::LinSpaced(nv, 0.0, 1.0 / 3.0);
  props[1].name = "u";
  props[1].values = positions.col(0).array().sin();
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string p = path(binary ? "rt_b.ply" : "rt_a.ply");
    write_ply(p, positions, mesh.faces, props, binary);
    EXPECT_FALSE(fs::exists(p + ".tmp"));
    const SurfaceInput s = read_surface(p);
    EXPECT_EQ(s.format, binary ? "ply-binary-le" : "ply-ascii");
    ASSERT_EQ(s.positions.rows(), nv);
    EXPECT_TRUE((s.positions.array() == positions.array()).all());
    EXPECT_TRUE(std::signbit(s.positions(1, 1)));
    EXPECT_EQ(s.triangles, mesh.faces);
    ASSERT_EQ(s.vertex_properties.size(), 2u);
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(s.vertex_properties[k].name, props[k].name);
      EXPECT_TRUE((s.vertex_properties[k].values.array() == props[k].values.array()).all());
    }
    // The header is the standard one MeshLab / ParaView read.
    std::ifstream in(p, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("element vertex " + std::to_string(nv) + "\nproperty double x\n"),
              std::string::npos);
    EXPECT_NE(text.find("element face " + std::to_string(mesh.faces.size()) +
                        "\nproperty list uchar int vertex_indices\nend_header\n"),
              std::string::npos);
  }
  // Without faces: a point cloud.
  write_ply(path("pc.ply"), positions, {});
  const SurfaceInput pc = read_surface(path("pc.ply"));
  EXPECT_FALSE(pc.has_faces());
  EXPECT_EQ(pc.positions.rows(), nv);
}

// Per-face properties (a field's singularities) round-trip in both encodings, next to vertex
// properties of the same name; a wrong count or a reserved name is refused without a file.
TEST_F(MeshIo, PlyFacePropertiesRoundTrip) {
  const auto mesh = intrinsic::icosphere(2);
  const Index nv = static_cast<Index>(mesh.positions.rows());
  const auto nf = static_cast<Eigen::Index>(mesh.faces.size());
  std::vector<VertexProperty> vertex(1), face(2);
  vertex[0] = {"singularity", Eigen::VectorXd::LinSpaced(nv, -1.0, 1.0)};
  face[0] = {"singularity", Eigen::VectorXd::LinSpaced(nf, -3.0, 4.0).array().round()};
  face[1] = {"area", Eigen::VectorXd::LinSpaced(nf, 0.0, 1e-300)};
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string p = path(binary ? "fp_b.ply" : "fp_a.ply");
    write_ply(p, mesh.positions, mesh.faces, vertex, face, binary);
    const SurfaceInput s = read_surface(p);
    EXPECT_EQ(s.triangles, mesh.faces);
    ASSERT_EQ(s.vertex_properties.size(), 1u);
    EXPECT_TRUE((s.vertex_properties[0].values.array() == vertex[0].values.array()).all());
    ASSERT_EQ(s.face_properties.size(), 2u);
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(s.face_properties[k].name, face[k].name);
      ASSERT_EQ(s.face_properties[k].values.size(), nf);
      EXPECT_TRUE((s.face_properties[k].values.array() == face[k].values.array()).all());
    }
  }
  const std::string bad = path("fp_bad.ply");
  std::vector<VertexProperty> short_face = {{"singularity", Eigen::VectorXd::Zero(nf - 1)}};
  EXPECT_THROW(write_ply(bad, mesh.positions, mesh.faces, {}, short_face), IoError);
  std::vector<VertexProperty> reserved = {{"vertex_indices", Eigen::VectorXd::Zero(nf)}};
  EXPECT_THROW(write_ply(bad, mesh.positions, mesh.faces, {}, reserved), IoError);
  EXPECT_FALSE(fs::exists(bad));
  // other readers' face properties (uchar colours, an int) are read as doubles
  std::ofstream(path("fp_other.ply"))
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty uchar red\nproperty list uchar int "
         "vertex_indices\nproperty int label\nend_header\n0 0 0\n1 0 0\n0 1 0\n200 3 0 1 2 -7\n";
  const SurfaceInput other = read_surface(path("fp_other.ply"));
  ASSERT_EQ(other.face_properties.size(), 2u);
  EXPECT_EQ(other.face_properties[0].name, "red");
  EXPECT_EQ(other.face_properties[0].values[0], 200.0);
  EXPECT_EQ(other.face_properties[1].values[0], -7.0);
}

TEST_F(MeshIo, WriterErrorsLeaveNoFile) {
  const auto mesh = intrinsic::tetrahedron();
  std::vector<VertexProperty> props(1);
  props[0].name = "short";
  props[0].values = Eigen::VectorXd::Zero(2);
  const std::string p = path("bad.ply");
  expect_io_error([&] { write_ply(p, mesh.positions, mesh.faces, props); }, {"bad.ply", "short"});
  EXPECT_FALSE(fs::exists(p));
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  std::vector<Triangle> bad_faces = {{0, 1, 9}};
  expect_io_error([&] { write_ply(p, mesh.positions, bad_faces); }, {"bad.ply", "out of range"});
  EXPECT_FALSE(fs::exists(p));
  const std::string nodir = path("missing_dir/x.ply");
  expect_io_error([&] { write_ply(nodir, mesh.positions, mesh.faces); }, {"x.ply"});
  EXPECT_FALSE(fs::exists(nodir + ".tmp"));
  expect_io_error([&] { write_values(nodir, Eigen::VectorXd::Ones(3)); }, {"x.ply"});
}

TEST_F(MeshIo, MatrixMarketRoundTripAndSymmetric) {
  std::mt19937 rng(3);
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < 200; ++k) {
    t.emplace_back(static_cast<int>(rng() % 40), static_cast<int>(rng() % 30),
                   std::ldexp(static_cast<double>(rng()), -20) - 1000.0);
  }
  Eigen::SparseMatrix<double> A(40, 30);
  A.setFromTriplets(t.begin(), t.end());
  const std::string p = path("a.mtx");
  write_matrix_market(p, A);
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  const Eigen::SparseMatrix<double> B = read_matrix_market(p);
  ASSERT_EQ(B.rows(), 40);
  ASSERT_EQ(B.cols(), 30);
  EXPECT_EQ(B.nonZeros(), A.nonZeros());
  EXPECT_EQ(Eigen::MatrixXd(A - B).cwiseAbs().maxCoeff(), 0.0);

  const auto s = write("s.mtx",
                       "%%MatrixMarket matrix coordinate real symmetric\n% comment\n"
                       "3 3 3\n1 1 2.5\n3 1 -1\n3 3 4\n");
  const Eigen::MatrixXd S = Eigen::MatrixXd(read_matrix_market(s));
  Eigen::MatrixXd expected(3, 3);
  expected << 2.5, 0, -1, 0, 0, 0, -1, 0, 4;
  EXPECT_EQ(S, expected);

  const auto bad = write("bad.mtx",
                         "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 "
                         "1\n3 1 1\n");
  expect_io_error([&] { read_matrix_market(bad); }, {"bad.mtx", "line 4", "out of range"});
  const auto few = write("few.mtx",
                         "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 "
                         "1\n");
  expect_io_error([&] { read_matrix_market(few); }, {"few.mtx", "line", "ends after 1 of 2"});
  const auto huge = write("huge.mtx",
                          "%%MatrixMarket matrix coordinate real general\n"
                          "2 2 4000000000\n1 1 1\n");
  expect_io_error([&] { read_matrix_market(huge); }, {"huge.mtx", "line 2", "4000000000"});
  const auto banner = write("banner.mtx", "hello\n");
  expect_io_error([&] { read_matrix_market(banner); }, {"banner.mtx", "line 1", "MatrixMarket"});
}

// Header counts that disagree with the content are errors with the numbers, never a silent
// partial read: an OFF or binary STL whose header declares fewer faces than the file holds, and
// a symmetric Matrix Market file whose size line is not square.
TEST_F(MeshIo, HeaderCountsMustMatchTheContent) {
  const auto off = write("under.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n");
  expect_read_error(off, "line 8", "declares 1 faces but the file goes on");
  std::string stl(80, ' ');
  const std::uint32_t declared = 1;
  stl.append(reinterpret_cast<const char*>(&declared), 4);
  for (int t = 0; t < 2; ++t) {
    float tri[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, float(t)};
    stl.append(reinterpret_cast<const char*>(tri), sizeof tri);
    stl.append(2, '\0');
  }
  expect_read_error(write("under.stl", stl), "134", "declares 1 triangles but the file holds 2");
  const auto skew = write("skew.mtx",
                          "%%MatrixMarket matrix coordinate real skew-symmetric\n"
                          "4 3 1\n2 1 1\n");
  expect_io_error([&] { read_matrix_market(skew); }, {"skew.mtx", "must be square", "4x3"});
  const auto huge = write("huge_size.mtx",
                          "%%MatrixMarket matrix coordinate pattern general\n"
                          "1031883662 8 2\n1 3\n2 1\n");
  expect_io_error([&] { read_matrix_market(huge); },
                  {"huge_size.mtx", "too large for its entries"});
}

TEST_F(MeshIo, ValuesRoundTrip) {
  Eigen::VectorXd v(7);
  v << 1.0 / 3.0, -0.0, 1e-310, std::numeric_limits<double>::infinity(),
      -std::numeric_limits<double>::infinity(), 12345678.9, -2.5e300;
  const std::string p = path("v.txt");
  write_values(p, v);
  EXPECT_FALSE(fs::exists(p + ".tmp"));
  const Eigen::VectorXd w = read_values(p);
  ASSERT_EQ(w.size(), v.size());
  for (int i = 0; i < v.size(); ++i) EXPECT_EQ(w[i], v[i]) << i;
  EXPECT_TRUE(std::signbit(w[1]));
  std::ifstream in(p);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\ninf\n-inf\n"), std::string::npos) << text;

  const Eigen::VectorXd c = read_values(write("c.txt", "# header\n1\n\n  nan\n+2.5 # two\n"));
  ASSERT_EQ(c.size(), 3);
  EXPECT_TRUE(std::isnan(c[1]));
  EXPECT_EQ(c[2], 2.5);
  expect_io_error([&] { read_values(write("b.txt", "1\n2 3\n")); }, {"b.txt", "line 2"});
  expect_io_error([&] { read_values(write("m.txt", "1\n2\n3q\n")); },
                  {"m.txt", "line 3", "malformed"});
  expect_io_error([&] { read_values(path("absent.txt")); }, {"absent.txt"});
}

// ---------------------------------------------------------------------------------- corpus

/// V and F columns of the file table in ../shared/data/MANIFEST.md ("-" F → -1).
std::map<std::string, std::pair<long, long>> manifest_counts() {
  std::map<std::string, std::pair<long, long>> counts;
  std::ifstream in(test::shared_data() / "MANIFEST.md");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    std::string cell;
    while (std::getline(ss, cell, '|')) cells.push_back(cell);
    if (cells.size() < 4) continue;
    auto trim = [](std::string s) {
      s.erase(0, s.find_first_not_of(" `"));
      s.erase(s.find_last_not_of(" `") + 1);
      return s;
    };
    const std::string f = trim(cells[3]);
    counts[trim(cells[0])] = {std::stol(trim(cells[2])), f == "-" ? -1L : std::stol(f)};
  }
  return counts;
}

TEST_F(MeshIo, SharedCorpusMatchesManifest) {
  IFEM_REQUIRE_SHARED_DATA();
  const auto counts = manifest_counts();
  ASSERT_FALSE(counts.empty()) << "no file table in MANIFEST.md";
  int checked = 0;
  for (const std::string sub : {"meshes", "pointclouds"}) {
    for (const auto& file : test::shared_files(sub)) {
      const std::string key = sub + "/" + file.filename().string();
      SCOPED_TRACE(key);
      const auto it = counts.find(key);
      ASSERT_NE(it, counts.end()) << "not in MANIFEST.md";
      const SurfaceInput s = read_surface(file.string());
      EXPECT_EQ(s.positions.rows(), it->second.first);
      if (it->second.second < 0) {
        EXPECT_FALSE(s.has_faces());
      } else {
        EXPECT_EQ(s.n_polygons, it->second.second);
        EXPECT_GE(static_cast<long>(s.triangles.size()), it->second.second);
      }
      if (key == "meshes/tet_with_self_edge.ply") {
        EXPECT_EQ(s.positions.rows(), 3);
        EXPECT_EQ(s.n_polygons, 2);
      }
      if (key == "pointclouds/oni.xyz" || key == "pointclouds/armadillo_points_normals.ply") {
        EXPECT_EQ(s.normals.rows(), s.positions.rows());
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, static_cast<int>(counts.size()));
}

}  // namespace
}  // namespace ifem::io
