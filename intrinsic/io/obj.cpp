// Wavefront OBJ reader. We do not use the packaged tinyobjloader: it reads line by line through
// iostreams, turns a malformed number into 0 without an error, accepts NaN coordinates and
// reports no line numbers, so both the error requirements and the load-speed target rule it out.
#include <charconv>
#include <limits>
#include <string_view>
#include <vector>

#include "intrinsic/io/detail.h"

namespace ifem::io::detail {
namespace {

/// Parses an optional integer in [b, e) for the vt / vn part of a face corner; true if ok.
bool skip_optional_int(const char*& b, const char* e) {
  if (b == e || *b == '/') return true;
  std::int64_t ignored = 0;
  const auto r = std::from_chars(b, e, ignored);
  if (r.ec != std::errc()) return false;
  b = r.ptr;
  return true;
}

/// Resolves one face corner token ("v", "v/vt", "v//vn", "v/vt/vn") to a 0-based vertex id.
Index parse_corner(const TextCursor& c, std::string_view token, std::size_t n_vertices) {
  const char* b = token.data();
  const char* e = b + token.size();
  if (b != e && *b == '+') ++b;
  std::int64_t v = 0;
  const auto r = std::from_chars(b, e, v);
  bool ok = r.ec == std::errc() && (r.ptr == e || *r.ptr == '/');
  if (ok && r.ptr != e) {
    const char* q = r.ptr + 1;  // after the first '/'
    ok = skip_optional_int(q, e);
    if (ok && q != e) {
      ok = *q == '/';
      ++q;
      ok = ok && skip_optional_int(q, e) && q == e;
    }
  }
  if (r.ec == std::errc::result_out_of_range) {
    c.fail("face index out of range " + quoted(token));
  }
  if (!ok) c.fail("malformed face vertex " + quoted(token));
  if (v == 0) c.fail("face index 0 is invalid (OBJ indices start at 1)");
  if (v < 0) {
    const std::int64_t resolved = static_cast<std::int64_t>(n_vertices) + v;
    if (resolved < 0) {
      c.fail("relative face index " + std::to_string(v) + " out of range (only " +
             std::to_string(n_vertices) + " vertices so far)");
    }
    return static_cast<Index>(resolved);
  }
  if (v > std::numeric_limits<Index>::max()) {
    c.fail("face index " + std::to_string(v) + " out of range");
  }
  return static_cast<Index>(v - 1);
}

}  // namespace

SurfaceInput read_obj(const std::string& path, const std::string& bytes,
                      const ProgressCallback* on_progress) {
  static const ProgressCallback kNone;
  ProgressMeter meter(on_progress ? *on_progress : kNone, "parse", double(bytes.size()) + 1.0);
  SurfaceInput out;
  out.format = "obj";
  std::vector<double> xyz;
  std::vector<Index> polygon;
  PolygonSink sink(out);
  const char* end = bytes.data() + bytes.size();
  TextCursor c(path, bytes.data(), end);
  while (c.next_content_line()) {
    const char* p = c.pos();
    meter.update(double(p - bytes.data()));
    const char k = p[0];
    const bool keyword_ends = p + 1 == end || is_blank(p[1]) || p[1] == '\n' || p[1] == '#';
    if (k == 'v' && keyword_ends) {
      c.token();
      const double x = c.number("x coordinate");
      const double y = c.number("y coordinate");
      const double z = c.number("z coordinate");
      xyz.push_back(x);
      xyz.push_back(y);
      xyz.push_back(z);
    } else if (k == 'f' && keyword_ends) {
      c.token();
      polygon.clear();
      const std::size_t n_vertices = xyz.size() / 3;
      while (!c.at_line_end()) polygon.push_back(parse_corner(c, c.token(), n_vertices));
      if (polygon.size() < 3) {
        c.fail("face with " + std::to_string(polygon.size()) + " vertices (at least 3 needed)");
      }
      sink.add(polygon.data(), polygon.size(), c.line());
    }
    // Everything else (vt, vn, l, o, g, s, mtllib, usemtl, ...) is ignored.
    c.next_line();
  }
  set_positions(out, xyz);
  out.normals.resize(0, 3);
  check_max_index(path, sink, static_cast<Index>(out.positions.rows()), false, 1);
  meter.finish();
  return out;
}

}  // namespace ifem::io::detail
