// The software rasterizer (solvers/recipes/render.h) against what an orthographic picture of a
// unit sphere must show: the projected disc's area, the colour map's order from top to bottom,
// one dark band per isoline at the row its level projects to, curves hidden behind the
// surface; the PNG read back to the same pixels; the same bytes twice.
#include "solvers/recipes/render.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/triangle_formulas.h"
#include "intrinsic/generators/mesh_generators.h"
#include "intrinsic/refine/common_subdivision.h"
#include "solvers/recipes/recipes.h"

namespace ifem::solvers {
namespace {

using intrinsic::kPi;

/// Unit icosphere coloured by height (y).
RenderScene sphere_by_height(int n = 16) {
  const intrinsic::TriangleMesh m = intrinsic::icosphere(n);
  RenderScene s;
  s.positions = m.positions;
  s.triangles = m.faces;
  s.field = m.positions.col(1);
  s.field_name = "y";
  return s;
}

void set_view(RenderOptions& o, const char* name) {
  const auto [azimuth, elevation] = named_view(name);
  o.azimuth_deg = azimuth;
  o.elevation_deg = elevation;
}

bool is_background(const Image& img, int x, int y, const RenderOptions& o) {
  return img.pixel(x, y) == o.background;
}

long count_foreground(const Image& img, const RenderOptions& o) {
  long n = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) n += !is_background(img, x, y, o);
  }
  return n;
}

TEST(Render, SizeAsAskedAndPngDecodesToThePixels) {
  RenderOptions o;
  o.width = 157;
  o.height = 93;
  const Image img = render_scene(sphere_by_height(4), o).image;
  ASSERT_EQ(img.width, 157);
  ASSERT_EQ(img.height, 93);
  ASSERT_EQ(img.rgb.size(), 157u * 93u * 3u);
  const std::vector<std::uint8_t> png = encode_png(img);
  ASSERT_GT(png.size(), 8u + 25u + 12u + 12u);
  EXPECT_EQ(std::string(png.begin() + 1, png.begin() + 4), "PNG");
  // IHDR: width and height big-endian at bytes 16..23, its CRC after the 13 data bytes
  auto u32 = [&](std::size_t at) {
    return (std::uint32_t(png[at]) << 24) | (std::uint32_t(png[at + 1]) << 16) |
           (std::uint32_t(png[at + 2]) << 8) | std::uint32_t(png[at + 3]);
  };
  EXPECT_EQ(u32(16), 157u);
  EXPECT_EQ(u32(20), 93u);
  EXPECT_EQ(u32(29), crc32(0L, png.data() + 12, 17));
  // IDAT right after IHDR: inflate, drop each row's filter byte, compare with the pixels
  const std::uint32_t idat_len = u32(33);
  ASSERT_EQ(std::string(png.begin() + 37, png.begin() + 41), "IDAT");
  std::vector<std::uint8_t> raw(93 * (1 + 157 * 3));
  uLongf raw_len = raw.size();
  ASSERT_EQ(uncompress(raw.data(), &raw_len, png.data() + 41, idat_len), Z_OK);
  ASSERT_EQ(raw_len, raw.size());
  for (int y = 0; y < 93; ++y) {
    ASSERT_EQ(raw[y * (1 + 157 * 3)], 0);
    ASSERT_TRUE(std::equal(img.rgb.begin() + y * 157 * 3, img.rgb.begin() + (y + 1) * 157 * 3,
                           raw.begin() + y * (1 + 157 * 3) + 1));
  }
  EXPECT_EQ(std::string(png.end() - 8, png.end() - 4), "IEND");
}

// The unit sphere's picture is a disc of radius fill · min(W, H) / 2: its pixel count lies
// between the inscribed polygon's disc shrunk by a pixel and the disc grown by a pixel.
TEST(Render, SphereCoversItsProjectedDisc) {
  const RenderScene s = sphere_by_height(16);
  // the icosphere's silhouette stays within cos(edge angle) of the unit circle
  const double inner = std::cos(1.2 / 16.0);
  struct Case {
    int w, h, ss;
    double fill;
  };
  for (const Case c : {Case{400, 300, 1, 0.9}, Case{300, 400, 2, 0.9}, Case{257, 131, 3, 0.5},
                       Case{200, 200, 1, 1.5}}) {
    RenderOptions o;
    o.width = c.w;
    o.height = c.h;
    o.supersample = c.ss;
    o.fill = c.fill;
    const long n = count_foreground(render_scene(s, o).image, o);
    const double r = c.fill * 0.5 * std::min(c.w, c.h);
    const double lo = kPi * std::pow(r * inner - 1.0, 2);
    const double hi = kPi * std::pow(r + 1.0, 2);
    if (r * inner - 1.0 >= 0.5 * std::hypot(c.w, c.h)) {  // zoomed in: the disc covers it all
      EXPECT_EQ(n, static_cast<long>(c.w) * c.h) << c.w << "x" << c.h << " fill " << c.fill;
      continue;
    }
    EXPECT_GE(n, lo) << c.w << "x" << c.h << " fill " << c.fill;
    EXPECT_LE(n, hi) << c.w << "x" << c.h << " fill " << c.fill;
  }
}

/// Mean of channel c / (R + G + B) over the foreground pixels of rows [y0, y1).
double chroma(const Image& img, const RenderOptions& o, int y0, int y1, int c) {
  double sum = 0.0;
  long n = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (is_background(img, x, y, o)) continue;
      const auto p = img.pixel(x, y);
      const double total = p[0] + p[1] + p[2];
      if (total > 0) sum += p[c] / total, ++n;
    }
  }
  return n > 0 ? sum / n : std::nan("");
}

double chroma_of(ColorMap map, double t, int c) {
  const auto p = colormap_color(map, t);
  return static_cast<double>(p[c]) / (p[0] + p[1] + p[2]);
}

// Shading scales a pixel's three channels alike, so the chromaticity (channel / sum) is the
// colour map's: the upper half (y > 0, high values) must have the map's upper colours.
TEST(Render, HeightColoursOrderedAsTheColourMap) {
  const RenderScene s = sphere_by_height(16);
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  for (const char* view : {"front", "back", "left", "right"}) {
    set_view(o, view);
    o.colormap = ColorMap::kViridis;  // blue share falls from violet (low) to yellow (high)
    Image img = render_scene(s, o).image;
    const double top = chroma(img, o, 0, o.height / 2, 2),
                 bottom = chroma(img, o, o.height / 2, o.height, 2);
    EXPECT_LT(top, chroma_of(ColorMap::kViridis, 0.5, 2)) << view;
    EXPECT_GT(bottom, chroma_of(ColorMap::kViridis, 0.5, 2)) << view;
    o.colormap = ColorMap::kDiverging;  // red above, blue below
    img = render_scene(s, o).image;
    EXPECT_GT(chroma(img, o, 0, o.height / 2 - 2, 0), chroma(img, o, 0, o.height / 2 - 2, 2))
        << view;
    EXPECT_GT(chroma(img, o, o.height / 2 + 2, o.height, 2),
              chroma(img, o, o.height / 2 + 2, o.height, 0))
        << view;
  }
  // from the top (camera on +y) only the upper hemisphere shows: every pixel above the middle
  // of the map; from below, every pixel under it
  for (const char* view : {"top", "bottom"}) {
    set_view(o, view);
    o.colormap = ColorMap::kDiverging;
    const Image img = render_scene(s, o).image;
    const bool up = std::string(view) == "top";
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        if (is_background(img, x, y, o)) continue;
        const auto p = img.pixel(x, y);
        const int high = up ? 0 : 2, low = up ? 2 : 0;  // red above the middle, blue below
        ASSERT_GE(p[high], p[low]) << view << " at " << x << "," << y;
      }
    }
  }
}

// N isolines of the height: N dark bands, each at the row its level projects to (orthographic:
// y = c lands on row H/2 − c · fill · min(W, H)/2), and nothing else changes.
TEST(Render, IsolinesAddOneBandPerLevelAtItsRow) {
  const RenderScene s = sphere_by_height(24);
  RenderOptions o;
  o.width = 300;
  o.height = 300;
  o.supersample = 1;
  const Image plain = render_scene(s, o).image;
  const double r = o.fill * 0.5 * o.height;
  for (int n : {1, 3, 7}) {
    o.isolines = n;
    const Image lines = render_scene(s, o).image;
    std::vector<double> rows;
    for (int k = 1; k <= n; ++k) rows.push_back(0.5 * o.height - r * (-1.0 + 2.0 * k / (n + 1)));
    long changed = 0;
    for (int y = 0; y < o.height; ++y) {
      for (int x = 0; x < o.width; ++x) {
        if (lines.pixel(x, y) == plain.pixel(x, y)) continue;
        ++changed;
        double nearest = 1e9;
        for (double row : rows) nearest = std::min(nearest, std::abs(y + 0.5 - row));
        ASSERT_LE(nearest, 2.0) << "changed pixel " << x << "," << y << " with " << n;
        const auto p = lines.pixel(x, y);
        ASSERT_LT(p[0] + p[1] + p[2], 3 * 60) << "an isoline pixel is dark";
      }
    }
    // the middle column crosses each band once
    int bands = 0;
    bool inside = false;
    for (int y = 0; y < o.height; ++y) {
      const bool c = lines.pixel(o.width / 2, y) != plain.pixel(o.width / 2, y);
      bands += c && !inside;
      inside = c;
    }
    EXPECT_EQ(bands, n);
    EXPECT_GT(changed, n * r) << "each isoline is a line across the disc";
  }
}

TEST(Render, SameBytesTwiceAndOptionsChangeThem) {
  RenderScene s = sphere_by_height(20);
  s.curves.push_back({{-1, 0, 1.0}, {1, 0, 1.0}});
  RenderOptions o;
  o.width = 200;
  o.height = 150;
  o.isolines = 5;
  o.wireframe = true;
  o.azimuth_deg = 30;
  o.elevation_deg = 20;
  const std::vector<std::uint8_t> a = encode_png(render_scene(s, o).image);
  const std::vector<std::uint8_t> b = encode_png(recipes::render(s, o).image);
  EXPECT_EQ(a, b);
  o.azimuth_deg = 31;
  EXPECT_NE(a, encode_png(render_scene(s, o).image));
}

bool has_red(const Image& img) {
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const auto p = img.pixel(x, y);
      if (p[0] > 150 && p[1] < 100 && p[2] < 100) return true;
    }
  }
  return false;
}

// A curve on the near side shows; the same curve on the far side is hidden by the surface.
TEST(Render, CurvesBehindTheSurfaceAreHidden) {
  RenderScene s = sphere_by_height(16);
  s.field.resize(0);  // grey surface: red can only come from the curve
  std::vector<Eigen::Vector3d> near, far;
  for (int k = 0; k <= 40; ++k) {
    const double a = -1.2 + 2.4 * k / 40.0;
    near.emplace_back(std::sin(a), 0.0, std::cos(a));
    far.emplace_back(std::sin(a), 0.0, -std::cos(a));
  }
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  s.curves = {near};
  EXPECT_TRUE(has_red(render_scene(s, o).image));
  s.curves = {far};
  EXPECT_FALSE(has_red(render_scene(s, o).image));
  o.azimuth_deg = 180;  // now the far curve faces the camera
  EXPECT_TRUE(has_red(render_scene(s, o).image));
}

// Non-finite values (unreachable vertices of a distance) are left out of the range and drawn
// grey; the diverging map's default range is symmetric about 0; a given range is kept.
TEST(Render, RangeOfTheFiniteValues) {
  RenderScene s = sphere_by_height(16);
  for (Eigen::Index i = 0; i < s.field.size(); ++i) {
    if (s.positions(i, 1) > 0.5) s.field[i] = std::numeric_limits<double>::infinity();
  }
  RenderOptions o;
  o.width = 120;
  o.height = 120;
  Rendering r = render_scene(s, o);
  EXPECT_EQ(r.range_lo, -1.0);
  EXPECT_LE(r.range_hi, 0.5);
  EXPECT_GT(r.range_hi, 0.4);
  const auto top = r.image.pixel(60, 60 - static_cast<int>(0.8 * 54));  // y ≈ 0.8: grey
  EXPECT_LE(std::max({top[0], top[1], top[2]}) - std::min({top[0], top[1], top[2]}), 2);
  const auto low = r.image.pixel(60, 60 + static_cast<int>(0.5 * 54));  // y ≈ −0.5: coloured
  EXPECT_GT(std::max({low[0], low[1], low[2]}) - std::min({low[0], low[1], low[2]}), 30);
  s.field = s.positions.col(1).array() + 0.5;
  o.colormap = ColorMap::kDiverging;
  r = render_scene(s, o);
  EXPECT_EQ(r.range_lo, -1.5);
  EXPECT_EQ(r.range_hi, 1.5);
  o.range_lo = -3.0;
  o.range_hi = 7.0;
  r = render_scene(s, o);
  EXPECT_EQ(r.range_lo, -3.0);
  EXPECT_EQ(r.range_hi, 7.0);
}

// The legend: the scene left of it is the picture of the narrower size; the bar runs from the
// map's top colour to its bottom one, with one dark tick per isoline; the labels are dark
// pixels left of the bar, more of them for a longer number.
TEST(Render, LegendBarAndLabels) {
  const RenderScene s = sphere_by_height(12);
  RenderOptions o;
  o.width = 320;
  o.height = 200;
  o.supersample = 1;
  o.legend = true;
  o.isolines = 3;
  const Rendering r = render_scene(s, o);
  ASSERT_GT(r.scene_width, o.width / 2);
  ASSERT_LT(r.scene_width, o.width);
  RenderOptions narrow = o;
  narrow.legend = false;
  narrow.width = r.scene_width;
  const Image left = render_scene(s, narrow).image;
  for (int y = 0; y < o.height; ++y) {
    for (int x = 0; x < r.scene_width; ++x) ASSERT_EQ(r.image.pixel(x, y), left.pixel(x, y));
  }
  const int bar_x = o.width - 4 - 4;  // the bar's middle column (font scale 1 at 200 rows)
  const int y0 = 20, y1 = 180;        // 0.1 H, 0.9 H
  auto near = [](std::array<std::uint8_t, 3> a, std::array<std::uint8_t, 3> b) {
    for (int c = 0; c < 3; ++c) {
      if (std::abs(a[c] - b[c]) > 3) return false;
    }
    return true;
  };
  EXPECT_TRUE(near(r.image.pixel(bar_x, y0), colormap_color(o.colormap, 1.0)));
  EXPECT_TRUE(near(r.image.pixel(bar_x, y1 - 1), colormap_color(o.colormap, 0.0)));
  int ticks = 0;
  for (int y = y0 + 1; y < y1 - 1; ++y) {
    const auto p = r.image.pixel(bar_x, y);
    ticks += p[0] + p[1] + p[2] < 3 * 30;
  }
  EXPECT_EQ(ticks, 3);
  auto ink = [&](const Image& img, int x0, int x1) {
    long n = 0;
    for (int y = 0; y < img.height; ++y) {
      for (int x = x0; x < x1; ++x) {
        const auto p = img.pixel(x, y);
        n += p[0] + p[1] + p[2] < 3 * 30;
      }
    }
    return n;
  };
  const long short_labels = ink(r.image, r.scene_width, bar_x - 6);  // "1", "-1"
  EXPECT_GT(short_labels, 10);
  RenderOptions wide = o;
  wide.range_lo = -1.23456;
  const Rendering longer = render_scene(s, wide);
  EXPECT_LT(longer.scene_width, r.scene_width);
  EXPECT_GT(ink(longer.image, longer.scene_width, bar_x - 6), short_labels);
  RenderScene no_field = s;
  no_field.field.resize(0);
  o.isolines = 0;
  EXPECT_THROW(render_scene(no_field, o), InvalidInput);
}

TEST(Render, PointCloudDrawnAsPoints) {
  RenderScene s = sphere_by_height(6);
  s.triangles.clear();
  RenderOptions o;
  o.width = 200;
  o.height = 200;
  o.point_size = 2.0;
  const long n = count_foreground(render_scene(s, o).image, o);
  EXPECT_GT(n, s.positions.rows() / 2);  // the near half at least, points rarely overlap
  EXPECT_LE(n, s.positions.rows() * 9);  // a 2-pixel square touches at most 3×3 pixels
}

TEST(Render, RefusesWhatItCannotDraw) {
  RenderScene s = sphere_by_height(2);
  RenderOptions o;
  o.isolines = 2;
  RenderScene no_field = s;
  no_field.field.resize(0);
  EXPECT_THROW(render_scene(no_field, o), InvalidInput);
  RenderScene short_field = s;
  short_field.field.resize(3);
  EXPECT_THROW(render_scene(short_field, {}), InvalidInput);
  RenderScene bad_face = s;
  bad_face.triangles[0][1] = static_cast<Index>(s.positions.rows());
  EXPECT_THROW(render_scene(bad_face, {}), InvalidInput);
  for (auto edit : std::vector<void (*)(RenderOptions&)>{
           [](RenderOptions& r) { r.width = 0; }, [](RenderOptions& r) { r.supersample = 5; },
           [](RenderOptions& r) { r.elevation_deg = 91; },
           [](RenderOptions& r) { r.width = 16384, r.height = 16384; },
           [](RenderOptions& r) { r.range_lo = 1, r.range_hi = 1; }}) {
    RenderOptions bad;
    edit(bad);
    EXPECT_THROW(bad.validate(), InvalidInput);
  }
  EXPECT_THROW(named_view("side"), InvalidInput);
  EXPECT_THROW(colormap_from_name("jet"), InvalidInput);
}

TEST(Render, ReadsPolylinesOfAnObjFile) {
  const auto path = std::filesystem::temp_directory_path() / "ifem_render_test_lines.obj";
  std::ofstream(path) << "# curves\nv 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\nl -1 1\nl 2\n";
  const auto lines = read_polylines_obj(path.string());
  ASSERT_EQ(lines.size(), 2u);  // the one-point 'l' line is dropped
  EXPECT_EQ(lines[0].size(), 3u);
  EXPECT_EQ(lines[1][0], Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(lines[1][1], Eigen::Vector3d(0, 0, 0));
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nl 1 3\n";
  try {
    read_polylines_obj(path.string());
    ADD_FAILURE() << "an id out of range was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// PLY line sets as ifem refine --lines writes them (binary and ASCII) read back polyline by
// polyline; a big-endian file with an extra element; refusals name the problem.
TEST(Render, ReadsPlyLineSets) {
  const std::vector<std::vector<Eigen::Vector3d>> lines = {{{0, 0, 0}, {1, 0, 0}, {1, 2, 0.5}},
                                                           {{-1, -1, -1}, {0.25, 0.5, 1e-3}}};
  const auto path =
      (std::filesystem::temp_directory_path() / "ifem_render_test_lines.ply").string();
  for (bool binary : {true, false}) {
    intrinsic::write_polylines_ply(path, lines, binary, "test");
    EXPECT_EQ(read_polylines(path), lines) << (binary ? "binary" : "ascii");
  }
  std::string be =
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 0\nproperty uchar flags\n"
      "element edge 1\nproperty ushort vertex2\nproperty ushort vertex1\nend_header\n";
  const unsigned char body[] = {0x3f, 0x80, 0, 0, 0,    0,    0, 0, 0xc0, 0, 0, 0, 7,  // 1 0 -2
                                0,    0,    0, 0, 0x40, 0x40, 0, 0, 0,    0, 0, 0, 9,  // 0 3 0
                                0,    0,    0, 1};                                     // 1 → 0
  be.append(reinterpret_cast<const char*>(body), sizeof body);
  std::ofstream(path, std::ios::binary) << be;
  const auto read = read_polylines(path);
  ASSERT_EQ(read.size(), 1u);
  ASSERT_EQ(read[0].size(), 2u);
  EXPECT_EQ(read[0][0], Eigen::Vector3d(0, 3, 0));  // vertex1 = 1 (listed second)
  EXPECT_EQ(read[0][1], Eigen::Vector3d(1, 0, -2));
  auto refused = [&](const std::string& text, const std::string& why) {
    std::ofstream(path, std::ios::binary) << text;
    try {
      read_polylines(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\n";
  refused(head + "end_header\n0 0 0\n1 1 1\n", "needs 'vertex' and 'edge' elements");
  refused(head +
              "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
              "0 0 0\n1 1 1\n0 2\n",
          "edge 0: vertex ids must be in [0, 2)");
  refused(head +
              "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
              "0 0 0\n1 nan 1\n0 1\n",
          "vertex 1: not a finite number");
  refused(head + "element edge 1\nproperty int vertex1\nend_header\n0 0 0\n1 1 1\n0\n",
          "needs vertex1 and vertex2");
  refused(head +
              "element edge 3\nproperty int vertex1\nproperty int vertex2\nend_header\n"
              "0 0 0\n1 1 1\n0 1\n",
          "edge 1: truncated");
  std::filesystem::remove(path);
  EXPECT_THROW(read_polylines("lines.txt"), IoError);
}

// Damaged files (bytes changed, cut short) either read or throw IoError: never another
// exception, a crash or a hang (scripts/sanitize.sh runs this under AddressSanitizer too).
TEST(Render, DamagedPolylineFilesThrowIoErrorOnly) {
  const std::vector<std::vector<Eigen::Vector3d>> lines = {{{0, 0, 0}, {1, 0, 0}, {1, 2, 0.5}},
                                                           {{-1, -1, -1}, {0.25, 0.5, 1e-3}}};
  const auto dir = std::filesystem::temp_directory_path();
  std::vector<std::pair<std::string, std::string>> originals;  // extension, bytes
  for (bool binary : {true, false}) {
    const std::string p = (dir / "ifem_render_damaged_src.ply").string();
    intrinsic::write_polylines_ply(p, lines, binary, "damaged");
    std::ifstream in(p, std::ios::binary);
    originals.push_back({".ply", std::string(std::istreambuf_iterator<char>(in), {})});
    std::filesystem::remove(p);
  }
  originals.push_back({".obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\nl -1 1\n"});
  std::uint64_t state = 12345;
  auto next = [&]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<std::size_t>(state >> 33);
  };
  const char* bytes = "0123456789 -.\nexyzlv\xff\x00";
  int read = 0, refused = 0;
  for (const auto& [ext, original] : originals) {
    const std::string p = (dir / ("ifem_render_damaged" + ext)).string();
    for (int trial = 0; trial < 150; ++trial) {
      std::string text = original;
      if (trial % 5 == 0) {
        text.resize(next() % text.size());
      } else {
        for (int k = 0; k < 1 + trial % 3; ++k) text[next() % text.size()] = bytes[next() % 22];
      }
      std::ofstream(p, std::ios::binary) << text;
      try {
        read_polylines(p);
        ++read;
      } catch (const IoError&) {
        ++refused;
      }
    }
    std::filesystem::remove(p);
  }
  EXPECT_GT(read, 0);
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace ifem::solvers
