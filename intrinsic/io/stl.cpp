// STL reader (ASCII and binary). STL stores every triangle corner separately, so corners with
// exactly equal positions are welded into one vertex (numbered in order of first appearance)
// and the merged corners are counted in `welded_vertices`.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "intrinsic/io/detail.h"

namespace ifem::io::detail {
namespace {

constexpr std::size_t kBinaryHeader = 84;
constexpr std::size_t kBinaryTriangle = 50;

std::uint32_t load_u32_le(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 |
         std::uint32_t{b[3]} << 24;
}

float load_f32_le(const char* p) {
  const std::uint32_t bits = load_u32_le(p);
  float v;
  std::memcpy(&v, &bits, sizeof(v));
  return v;
}

bool starts_with_solid(const std::string& bytes) {
  std::size_t k = 0;
  while (k < bytes.size() && (is_blank(bytes[k]) || bytes[k] == '\n')) ++k;
  return bytes.compare(k, 5, "solid") == 0;
}

/// Binary when the size matches the triangle count in the header exactly (even if the 80-byte
/// comment starts with "solid", as many exporters write); ASCII when it starts with "solid" and
/// holds no NUL byte (binary floats and attribute counts almost always contain one); otherwise
/// binary (and then too short means truncated).
bool is_binary_stl(const std::string& bytes) {
  if (bytes.size() >= kBinaryHeader) {
    const std::uint64_t n = load_u32_le(bytes.data() + 80);
    if (kBinaryHeader + kBinaryTriangle * n == bytes.size()) return true;
  }
  if (!starts_with_solid(bytes)) return true;
  return std::memchr(bytes.data(), '\0', bytes.size()) != nullptr;
}

/// Welds corners with exactly equal coordinates (−0 == +0); returns the vertex of each corner.
std::vector<Index> weld(const std::vector<double>& corners, std::vector<double>& xyz) {
  const std::size_t m = corners.size() / 3;
  std::vector<Index> order(m);
  std::iota(order.begin(), order.end(), Index{0});
  auto key = [&](Index c, int k) { return corners[3 * static_cast<std::size_t>(c) + k] + 0.0; };
  std::sort(order.begin(), order.end(), [&](Index a, Index b) {
    for (int k = 0; k < 3; ++k) {
      const double ka = key(a, k);
      const double kb = key(b, k);
      if (ka != kb) return ka < kb;
    }
    return a < b;
  });
  std::vector<Index> representative(m);
  for (std::size_t s = 0; s < m; ++s) {
    const Index c = order[s];
    const bool same = s > 0 && key(order[s - 1], 0) == key(c, 0) &&
                      key(order[s - 1], 1) == key(c, 1) && key(order[s - 1], 2) == key(c, 2);
    representative[c] = same ? representative[order[s - 1]] : c;
  }
  std::vector<Index> vertex(m);
  Index n = 0;
  for (std::size_t c = 0; c < m; ++c) {
    if (representative[c] == static_cast<Index>(c)) {
      vertex[c] = n++;
      xyz.insert(xyz.end(), corners.begin() + 3 * c, corners.begin() + 3 * c + 3);
    } else {
      vertex[c] = vertex[representative[c]];
    }
  }
  return vertex;
}

/// The raw corners of an STL file, facet by facet, before welding.
struct StlFacets {
  std::vector<double> corners;           // x, y, z of every corner, in file order
  std::vector<std::size_t> facet_sizes;  // corners per facet
  std::vector<std::size_t> facet_where;  // line or byte offset of each facet
};

/// Reads the triangles of a binary STL (size and count checked, coordinates finite).
void read_binary_facets(const std::string& path, const std::string& bytes, StlFacets& in) {
  if (bytes.size() < kBinaryHeader) {
    fail_offset(path, bytes.size(),
                "truncated binary STL: the header needs 84 bytes, the file "
                "has " +
                    std::to_string(bytes.size()));
  }
  const std::uint64_t n = load_u32_le(bytes.data() + 80);
  const std::uint64_t complete = (bytes.size() - kBinaryHeader) / kBinaryTriangle;
  if (complete < n) {
    fail_offset(path, kBinaryHeader + kBinaryTriangle * complete,
                "truncated binary STL: the header declares " + std::to_string(n) +
                    " triangles, the file holds " + std::to_string(complete));
  }
  if (complete > n) {  // a header that undercounts would silently drop triangles
    fail_offset(path, kBinaryHeader + kBinaryTriangle * n,
                "the header declares " + std::to_string(n) + " triangles but the file holds " +
                    std::to_string(complete));
  }
  checked_index(3 * n, "read_stl: corner count");
  in.corners.reserve(9 * n);
  in.facet_sizes.assign(n, 3);
  in.facet_where.resize(n);
  for (std::uint64_t t = 0; t < n; ++t) {
    const std::size_t at = kBinaryHeader + kBinaryTriangle * t;
    in.facet_where[t] = at;
    for (int k = 0; k < 9; ++k) {
      const double v = load_f32_le(bytes.data() + at + 12 + 4 * k);
      if (!std::isfinite(v)) {
        fail_offset(path, at + 12 + 4 * k,
                    "NaN or infinite coordinate in triangle #" + std::to_string(t));
      }
      in.corners.push_back(v);
    }
  }
}

/// Reads the facets of an ASCII STL (solid / facet / outer loop / vertex ... keywords).
void read_ascii_facets(const std::string& path, const std::string& bytes, StlFacets& in) {
  TextCursor c(path, bytes.data(), bytes.data() + bytes.size(), '\0');
  bool in_facet = false;
  std::size_t facet_corners = 0;
  while (c.next_content_line()) {
    const std::string_view keyword = c.token();
    if (keyword == "facet") {
      if (in_facet) c.fail("'facet' inside a facet (missing 'endfacet')");
      in_facet = true;
      facet_corners = 0;
      in.facet_where.push_back(c.line());
    } else if (keyword == "vertex") {
      if (!in_facet) c.fail("'vertex' outside a facet");
      in.corners.push_back(c.number("x coordinate"));
      in.corners.push_back(c.number("y coordinate"));
      in.corners.push_back(c.number("z coordinate"));
      ++facet_corners;
    } else if (keyword == "endfacet") {
      if (!in_facet) c.fail("'endfacet' without 'facet'");
      if (facet_corners < 3) {
        c.fail("facet with " + std::to_string(facet_corners) + " vertices (at least 3 needed)");
      }
      in.facet_sizes.push_back(facet_corners);
      in_facet = false;
    } else if (keyword != "solid" && keyword != "endsolid" && keyword != "outer" &&
               keyword != "endloop") {
      c.fail("unexpected keyword " + quoted(keyword) + " in ASCII STL");
    }
    c.next_line();
  }
  if (in_facet) c.fail("the file ends inside a facet (truncated?)");
}

}  // namespace

SurfaceInput read_stl(const std::string& path, const std::string& bytes) {
  SurfaceInput out;
  StlFacets in;
  if (is_binary_stl(bytes)) {
    out.format = "stl-binary";
    read_binary_facets(path, bytes, in);
  } else {
    out.format = "stl-ascii";
    read_ascii_facets(path, bytes, in);
  }
  std::vector<double> xyz;
  const std::vector<Index> vertex = weld(in.corners, xyz);
  out.welded_vertices = checked_index(vertex.size() - xyz.size() / 3, "read_stl");
  PolygonSink sink(out);
  std::size_t first = 0;
  for (std::size_t f = 0; f < in.facet_sizes.size(); ++f) {
    sink.add(vertex.data() + first, in.facet_sizes[f], in.facet_where[f]);
    first += in.facet_sizes[f];
  }
  set_positions(out, xyz);
  out.normals.resize(0, 3);
  return out;
}

}  // namespace ifem::io::detail
