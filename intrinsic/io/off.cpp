// OFF reader (OFF / COFF / NOFF / CNOFF / STOFF headers, or none): per-vertex extra columns and
// per-face colour columns are ignored, NOFF normals are kept; '#' comments are allowed.
#include <string_view>
#include <vector>

#include "intrinsic/io/detail.h"

namespace ifem::io::detail {

namespace {

// The nf face lines ("n i0 i1 ... [colour]") into out's polygons; nothing may follow them.
void read_off_faces(TextCursor& c, std::int64_t nf, std::int64_t nv, SurfaceInput& out) {
  PolygonSink sink(out);
  std::vector<Index> polygon;
  for (std::int64_t f = 0; f < nf; ++f) {
    if (!c.next_content_line()) {
      c.fail("file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    }
    const std::int64_t n = c.integer("face vertex count");
    if (n < 3) c.fail("face with " + std::to_string(n) + " vertices (at least 3 needed)");
    if (n > static_cast<std::int64_t>(c.remaining())) {
      c.fail("face vertex count " + std::to_string(n) + " too large");
    }
    polygon.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t v = c.integer("face index");
      if (v < 0 || v >= nv) {
        c.fail("face index " + std::to_string(v) + " out of range (the file has " +
               std::to_string(nv) + " vertices)");
      }
      polygon.push_back(static_cast<Index>(v));
    }
    sink.add(polygon.data(), polygon.size(), c.line());
    c.next_line();  // per-face colour columns are ignored
  }
  if (c.next_content_line()) {  // a header that undercounts would silently drop faces
    c.fail("the header declares " + std::to_string(nf) +
           " faces but the file goes on after them (a wrong face count in the header?)");
  }
}

}  // namespace

SurfaceInput read_off(const std::string& path, const std::string& bytes) {
  SurfaceInput out;
  out.format = "off";
  const char* end = bytes.data() + bytes.size();
  TextCursor c(path, bytes.data(), end);
  if (!c.next_content_line()) fail_file(path, "empty file (no OFF header)");
  bool has_normals = false;
  const char first = *c.pos();
  if (!(first >= '0' && first <= '9')) {
    const std::string_view header = c.token();
    const std::size_t k = header.size();
    const bool is_off = k >= 3 && header.substr(k - 3) == "OFF";
    if (!is_off) c.fail("not an OFF file: header " + quoted(header));
    for (char flag : header.substr(0, k - 3)) {
      if (flag == 'N') {
        has_normals = true;
      } else if (flag != 'C' && flag != 'S' && flag != 'T') {
        c.fail("unsupported OFF header " + quoted(header) + " (only [ST][C][N]OFF)");
      }
    }
    if (c.at_line_end() && !c.next_content_line()) c.fail("missing vertex and face counts");
  }
  const std::int64_t nv = c.integer("vertex count");
  const std::int64_t nf = c.integer("face count");
  const auto remaining = static_cast<std::int64_t>(end - c.pos());
  if (nv < 0 || nf < 0) c.fail("negative vertex or face count");
  // Each vertex needs at least 5 bytes and each face 7: refuse counts the file cannot hold
  // before allocating anything.
  if (nv > remaining / 5 || nf > remaining / 7) {
    c.fail("header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
           " faces but only " + std::to_string(remaining) + " bytes follow (truncated file?)");
  }
  c.next_line();
  std::vector<double> xyz;
  std::vector<double> nxyz;
  xyz.reserve(static_cast<std::size_t>(3 * nv));
  if (has_normals) nxyz.reserve(static_cast<std::size_t>(3 * nv));
  for (std::int64_t i = 0; i < nv; ++i) {
    if (!c.next_content_line()) {
      c.fail("file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    }
    xyz.push_back(c.number("x coordinate"));
    xyz.push_back(c.number("y coordinate"));
    xyz.push_back(c.number("z coordinate"));
    if (has_normals) {
      nxyz.push_back(c.number("normal x"));
      nxyz.push_back(c.number("normal y"));
      nxyz.push_back(c.number("normal z"));
    }
    c.next_line();  // colours and texture coordinates are ignored
  }
  read_off_faces(c, nf, nv, out);
  set_positions(out, xyz);
  out.normals.resize(0, 3);
  if (has_normals) set_normals(out, nxyz);
  return out;
}

SurfaceInput read_xyz(const std::string& path, const std::string& bytes) {
  SurfaceInput out;
  out.format = "xyz";
  TextCursor c(path, bytes.data(), bytes.data() + bytes.size());
  std::vector<double> xyz;
  std::vector<double> nxyz;
  int columns = 0;
  static const char* const kWhat[6] = {"x coordinate", "y coordinate", "z coordinate",
                                       "normal x",     "normal y",     "normal z"};
  while (c.next_content_line()) {
    double values[6];
    int n = 0;
    while (!c.at_line_end()) {
      if (n == 6) c.fail("too many values on a line (expected x y z [nx ny nz])");
      values[n] = c.number(kWhat[n]);
      ++n;
    }
    if (n != 3 && n != 6) {
      c.fail(std::to_string(n) + " values on a line (expected x y z [nx ny nz])");
    }
    if (columns == 0) columns = n;
    if (n != columns) {
      c.fail(std::to_string(n) + " values on a line but earlier lines have " +
             std::to_string(columns));
    }
    xyz.insert(xyz.end(), values, values + 3);
    if (n == 6) nxyz.insert(nxyz.end(), values + 3, values + 6);
    c.next_line();
  }
  set_positions(out, xyz);
  out.normals.resize(0, 3);
  if (columns == 6) set_normals(out, nxyz);
  return out;
}

}  // namespace ifem::io::detail
