// The files of render.h: PNG out (chunks written here, deflate and CRC-32 from zlib) and the
// polylines in (curves drawn over the surface): OBJ 'l' lines, PLY line sets.
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/mesh_io.h"
#include "intrinsic/io/tokens.h"
#include "solvers/recipes/render.h"

namespace ifem::solvers {

namespace {

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

/// length, type, data, CRC-32 of type + data (PNG spec, section 5.3)
void put_chunk(std::vector<std::uint8_t>& out, const char type[4],
               const std::vector<std::uint8_t>& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, out.data() + start, static_cast<uInt>(out.size() - start));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

/// One scalar property of a PLY element: its byte size (0 for a list) and whether it is x, y, z
/// (0..2) of a vertex or vertex1 / vertex2 (0..1) of an edge (-1: skipped).
struct LineSetProperty {
  std::string type;
  int size = 0;
  int role = -1;
};

struct LineSetElement {
  std::string name;
  std::size_t count = 0;
  std::vector<LineSetProperty> properties;
};

int ply_type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
      t == "float32") {
    return 4;
  }
  if (t == "double" || t == "float64") return 8;
  return -1;
}

/// A binary scalar of PLY type `t` at `p` as a double, bytes swapped when `swap`.
double ply_binary_value(const std::string& t, const unsigned char* p, int size, bool swap) {
  unsigned char b[8];
  for (int i = 0; i < size; ++i) b[i] = swap ? p[size - 1 - i] : p[i];
  auto get = [&](auto v) {
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  };
  if (t == "char" || t == "int8") return get(std::int8_t{});
  if (t == "uchar" || t == "uint8") return get(std::uint8_t{});
  if (t == "short" || t == "int16") return get(std::int16_t{});
  if (t == "ushort" || t == "uint16") return get(std::uint16_t{});
  if (t == "int" || t == "int32") return get(std::int32_t{});
  if (t == "uint" || t == "uint32") return get(std::uint32_t{});
  if (t == "float" || t == "float32") return get(float{});
  return get(double{});
}

/// The header of a PLY line set; `body` is set to the first byte after end_header.
std::vector<LineSetElement> line_set_header(const std::string& path, const std::string& text,
                                            std::size_t& body, std::string& format) {
  std::vector<LineSetElement> elements;
  std::size_t pos = 0, line_no = 0;
  while (true) {
    const std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) io::detail::fail_file(path, "no end_header");
    const std::vector<std::string> t = io::line_tokens(text.substr(pos, end - pos));
    ++line_no;
    pos = end + 1;
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info" || t[0] == "ply") continue;
    if (t[0] == "end_header") break;
    if (t[0] == "format" && t.size() >= 2) {
      format = t[1];
    } else if (t[0] == "element" && t.size() == 3) {
      long long n = 0;
      if (!io::parse_whole_integer(t[2], n) || n < 0) {
        io::detail::fail_line(path, line_no, "bad element count " + io::quoted_excerpt(t[2]));
      }
      elements.push_back({t[1], static_cast<std::size_t>(n), {}});
    } else if (t[0] == "property" && !elements.empty() && t.size() >= 3) {
      LineSetProperty p;
      p.type = t[1];
      p.size = t[1] == "list" ? 0 : ply_type_size(t[1]);
      if (p.size < 0)
        io::detail::fail_line(path, line_no, "unknown type " + io::quoted_excerpt(t[1]));
      const std::string& name = t.back();
      const std::string& el = elements.back().name;
      if (el == "vertex") p.role = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
      if (el == "edge") p.role = name == "vertex1" ? 0 : name == "vertex2" ? 1 : -1;
      elements.back().properties.push_back(p);
    } else {
      io::detail::fail_line(path, line_no, "unexpected header line");
    }
  }
  body = pos;
  return elements;
}

/// The scalars of one item of `e` (a list property only in an ASCII element that is neither
/// vertex nor edge, whose line is then skipped): values by role into `out`.
bool read_item(const std::string& path, const std::string& text, bool ascii, bool swap,
               const LineSetElement& e, std::size_t item, std::size_t& pos, double out[3]) {
  const std::string where = e.name + " " + std::to_string(item) + ": ";
  if (ascii) {
    if (pos >= text.size()) io::detail::fail_file(path, where + "truncated");
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    const std::vector<std::string> t = io::line_tokens(text.substr(pos, end - pos));
    pos = end + 1;
    if (e.name != "vertex" && e.name != "edge") return false;  // skipped whatever it holds
    if (t.size() < e.properties.size()) {
      io::detail::fail_file(path, where + "expected " + std::to_string(e.properties.size()) +
                                      " values, got " + std::to_string(t.size()));
    }
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      double v = 0.0;
      if (!io::parse_whole_real(t[k], v)) {
        io::detail::fail_file(path, where + "not a finite number: " + io::quoted_excerpt(t[k]));
      }
      if (e.properties[k].role >= 0) out[e.properties[k].role] = v;
    }
    return true;
  }
  for (const LineSetProperty& p : e.properties) {
    if (p.size == 0) {
      io::detail::fail_file(path, "list properties of the '" + e.name +
                                      "' element are not read in a binary line set");
    }
    if (pos + p.size > text.size()) io::detail::fail_file(path, where + "truncated");
    const double v =
        ply_binary_value(p.type, reinterpret_cast<const unsigned char*>(&text[pos]), p.size, swap);
    if (p.role >= 0) out[p.role] = v;
    pos += p.size;
  }
  return e.name == "vertex" || e.name == "edge";
}

/// A vertex element needs x, y, z and an edge element vertex1, vertex2, each once.
void check_roles(const std::string& path, const LineSetElement& e) {
  const int needed = e.name == "vertex" ? 3 : e.name == "edge" ? 2 : 0;
  int seen[3] = {0, 0, 0};
  for (const LineSetProperty& p : e.properties) {
    if (p.role >= 0) ++seen[p.role];
  }
  for (int r = 0; r < needed; ++r) {
    if (seen[r] != 1) {
      io::detail::fail_file(path, "the '" + e.name + "' element needs " +
                                      (needed == 3 ? "x, y and z" : "vertex1 and vertex2") +
                                      ", each once");
    }
  }
}

/// Consecutive edges sharing an end (b of one = a of the next) joined into one polyline.
std::vector<std::vector<Eigen::Vector3d>> join_edges(
    const std::string& path, const std::vector<Eigen::Vector3d>& points,
    const std::vector<std::array<double, 2>>& edges) {
  std::vector<std::vector<Eigen::Vector3d>> lines;
  long long last = -1;
  const double n = static_cast<double>(points.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const double a = edges[i][0], b = edges[i][1];
    if (!(a >= 0 && a < n && b >= 0 && b < n) || a != std::floor(a) || b != std::floor(b)) {
      io::detail::fail_file(path, "edge " + std::to_string(i) + ": vertex ids must be in [0, " +
                                      std::to_string(points.size()) + ")");
    }
    if (static_cast<long long>(a) != last) lines.push_back({points[static_cast<std::size_t>(a)]});
    lines.back().push_back(points[static_cast<std::size_t>(b)]);
    last = static_cast<long long>(b);
  }
  return lines;
}

}  // namespace

std::vector<std::uint8_t> encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
    throw InvalidInput("encode_png: the image's size does not match its pixels");
  }
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  put_u32(header, static_cast<std::uint32_t>(image.width));
  put_u32(header, static_cast<std::uint32_t>(image.height));
  header.insert(header.end(), {8, 2, 0, 0, 0});  // 8 bits, RGB, deflate, filter set 0, no interlace
  put_chunk(out, "IHDR", header);
  const std::size_t row = static_cast<std::size_t>(image.width) * 3;
  std::vector<std::uint8_t> raw;
  raw.reserve((row + 1) * image.height);
  for (int y = 0; y < image.height; ++y) {
    raw.push_back(0);  // filter type 0 (none)
    raw.insert(raw.end(), image.rgb.begin() + y * row, image.rgb.begin() + (y + 1) * row);
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> packed(packed_size);
  if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 6) !=
      Z_OK) {
    throw Error("encode_png: zlib failed to compress the image");
  }
  packed.resize(packed_size);
  put_chunk(out, "IDAT", packed);
  put_chunk(out, "IEND", {});
  return out;
}

void write_png(const std::string& path, const Image& image) {
  const std::vector<std::uint8_t> bytes = encode_png(image);
  io::detail::write_file_atomically(path, std::string(bytes.begin(), bytes.end()));
}

std::vector<std::vector<Eigen::Vector3d>> read_polylines_ply(const std::string& path) {
  const std::string text = io::detail::read_file(path);
  if (text.rfind("ply", 0) != 0) io::detail::fail_file(path, "not a PLY file");
  std::size_t pos = 0;
  std::string format;
  const std::vector<LineSetElement> elements = line_set_header(path, text, pos, format);
  const bool ascii = format == "ascii", swap = format == "binary_big_endian";
  if (!ascii && !swap && format != "binary_little_endian") {
    io::detail::fail_file(path, "unknown format " + io::quoted_excerpt(format));
  }
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<double, 2>> edges;
  bool has_vertex = false, has_edge = false;
  for (const LineSetElement& e : elements) {
    has_vertex |= e.name == "vertex";
    has_edge |= e.name == "edge";
    check_roles(path, e);
    if (!ascii && e.properties.empty()) continue;  // items of no bytes
    for (std::size_t i = 0; i < e.count; ++i) {
      double v[3] = {0.0, 0.0, 0.0};
      if (!read_item(path, text, ascii, swap, e, i, pos, v)) continue;
      if (e.name == "vertex") points.emplace_back(v[0], v[1], v[2]);
      if (e.name == "edge") edges.push_back({v[0], v[1]});
    }
  }
  if (!has_vertex || !has_edge) {
    io::detail::fail_file(path,
                          "a PLY line set needs 'vertex' and 'edge' elements (as ifem "
                          "refine --lines writes)");
  }
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) io::detail::fail_file(path, "a vertex position is not finite");
  }
  return join_edges(path, points, edges);
}

std::vector<std::vector<Eigen::Vector3d>> read_polylines(const std::string& path) {
  const std::string ext = io::file_extension(path);
  if (ext == ".obj") return read_polylines_obj(path);
  if (ext == ".ply") return read_polylines_ply(path);
  throw IoError(path +
                ": polylines are read from .obj ('l' lines) or .ply (vertex + edge "
                "elements), not " +
                (ext.empty() ? std::string("a file without extension") : ext));
}

std::vector<std::vector<Eigen::Vector3d>> read_polylines_obj(const std::string& path) {
  std::istringstream text(io::detail::read_file(path));
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<Eigen::Vector3d>> lines;
  std::size_t line_no = 0;
  for (std::string line; std::getline(text, line);) {
    ++line_no;
    const std::vector<std::string> tokens = io::line_tokens(line);
    if (tokens.empty()) continue;
    if (tokens[0] == "v") {
      Eigen::Vector3d p;
      if (tokens.size() < 4 || !io::parse_whole_real(tokens[1], p.x()) ||
          !io::parse_whole_real(tokens[2], p.y()) || !io::parse_whole_real(tokens[3], p.z())) {
        io::detail::fail_line(
            path, line_no,
            "a 'v' line needs three finite numbers, got " + io::quoted_excerpt(line));
      }
      points.push_back(p);
    } else if (tokens[0] == "l") {
      std::vector<Eigen::Vector3d> polyline;
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        long long id = 0;
        // "i/t" (a texture coordinate after the point's id) is allowed; the id comes first
        const std::string head = tokens[k].substr(0, tokens[k].find('/'));
        const long long n = static_cast<long long>(points.size());
        if (!io::parse_whole_integer(head, id) || id == 0 || id > n || id < -n) {
          io::detail::fail_line(path, line_no,
                                "point id " + io::quoted_excerpt(tokens[k]) + " is not in 1.." +
                                    std::to_string(n) + " (or -" + std::to_string(n) + "..-1)");
        }
        polyline.push_back(points[id > 0 ? id - 1 : n + id]);
      }
      if (polyline.size() >= 2) lines.push_back(std::move(polyline));
    }
  }
  return lines;
}

}  // namespace ifem::solvers
