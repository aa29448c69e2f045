// Mesh I/O entry points (format dispatch by extension), the PLY writer, Matrix Market and
// plain value files. The format readers live in intrinsic/io_*.cpp.
#include "intrinsic/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <set>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"

namespace ifem::io {

using detail::fail_file;

namespace {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(a[k])) !=
        std::tolower(static_cast<unsigned char>(b[k]))) {
      return false;
    }
  }
  return true;
}

template <class T>
void append_raw_le(std::string& out, T v) {
  unsigned char buf[sizeof(T)];
  std::memcpy(buf, &v, sizeof(T));
  if (!detail::host_is_little_endian()) std::reverse(buf, buf + sizeof(T));
  out.append(reinterpret_cast<const char*>(buf), sizeof(T));
}

}  // namespace

std::string file_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

SurfaceInput read_surface(const std::string& path, const ProgressCallback& on_progress) {
  const std::string ext = file_extension(path);
  using Reader = SurfaceInput (*)(const std::string&, const std::string&);
  Reader reader = nullptr;
  const bool obj = ext == ".obj";  // its reader also reports its parsing
  if (ext == ".off") reader = detail::read_off;
  if (ext == ".ply") reader = detail::read_ply;
  if (ext == ".stl") reader = detail::read_stl;
  if (ext == ".xyz" || ext == ".txt") reader = detail::read_xyz;
  if (reader == nullptr && !obj) {
    fail_file(path, "unknown extension " + detail::quoted(ext) +
                        " (expected .obj, .off, .ply, .stl, .xyz or .txt)");
  }
  const std::string bytes = detail::read_file(path, &on_progress);
  SurfaceInput s = obj ? detail::read_obj(path, bytes, &on_progress) : reader(path, bytes);
  detail::triangulate_polygons(s);
  if (s.positions.rows() == 0) fail_file(path, "no vertices (empty " + s.format + " file)");
  return s;
}

SurfaceInput read_mesh(const std::string& path) {
  SurfaceInput s = read_surface(path);
  if (!s.has_faces()) fail_file(path, "no faces (this is a point cloud; a mesh is needed)");
  return s;
}

namespace {

// Each property has `count` values and a name that is non-empty, without white space, and not
// taken (within its element).
void check_properties(const std::string& path, const std::vector<VertexProperty>& properties,
                      Eigen::Index count, const char* element, std::set<std::string> names) {
  for (const VertexProperty& p : properties) {
    if (p.values.size() != count) {
      fail_file(path, std::string(element) + " property " + detail::quoted(p.name) + " has " +
                          std::to_string(p.values.size()) + " values for " + std::to_string(count) +
                          " " + element + (count == 1 ? "" : "s"));
    }
    const bool bad_name = p.name.empty() || std::any_of(p.name.begin(), p.name.end(), [](char ch) {
                            return std::isspace(static_cast<unsigned char>(ch)) != 0;
                          });
    if (bad_name) fail_file(path, "invalid property name " + detail::quoted(p.name));
    if (!names.insert(p.name).second) {
      fail_file(path, "duplicate property name " + detail::quoted(p.name));
    }
  }
}

std::string ply_header(Eigen::Index nv, const std::vector<Triangle>& faces,
                       const std::vector<VertexProperty>& vertex_properties,
                       const std::vector<VertexProperty>& face_properties, bool binary) {
  std::string out = "ply\n";
  out += binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
  out += "comment written by ifem\n";
  out += "element vertex " + std::to_string(nv) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  for (const VertexProperty& p : vertex_properties) out += "property double " + p.name + "\n";
  if (!faces.empty()) {
    out += "element face " + std::to_string(faces.size()) + "\n";
    out += "property list uchar int vertex_indices\n";
    for (const VertexProperty& p : face_properties) out += "property double " + p.name + "\n";
  }
  out += "end_header\n";
  return out;
}

// The values of row i of `properties`, after what `out` holds (ASCII: each after a space).
void append_values(std::string& out, const std::vector<VertexProperty>& properties, Eigen::Index i,
                   bool binary) {
  for (const VertexProperty& p : properties) {
    if (binary) {
      append_raw_le(out, p.values[i]);
    } else {
      out.push_back(' ');
      detail::append_double(out, p.values[i]);
    }
  }
}

}  // namespace

void write_ply(const std::string& path, const Positions& positions,
               const std::vector<Triangle>& faces,
               const std::vector<VertexProperty>& vertex_properties, bool binary) {
  write_ply(path, positions, faces, vertex_properties, {}, binary);
}

void write_ply(const std::string& path, const Positions& positions,
               const std::vector<Triangle>& faces,
               const std::vector<VertexProperty>& vertex_properties,
               const std::vector<VertexProperty>& face_properties, bool binary) {
  const Eigen::Index nv = positions.rows();
  const auto nf = static_cast<Eigen::Index>(faces.size());
  check_properties(path, vertex_properties, nv, "vertex", {"x", "y", "z"});
  check_properties(path, face_properties, nf, "face", {"vertex_indices"});
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (Index v : faces[f]) {
      if (v < 0 || v >= nv) {
        fail_file(path, "face #" + std::to_string(f) + " has vertex index " + std::to_string(v) +
                            " out of range (" + std::to_string(nv) + " vertices)");
      }
    }
  }
  std::string out = ply_header(nv, faces, vertex_properties, face_properties, binary);
  const std::size_t columns = 3 + vertex_properties.size();
  out.reserve(out.size() + static_cast<std::size_t>(nv) * columns * (binary ? 8 : 20) +
              faces.size() * ((binary ? 13 : 24) + face_properties.size() * (binary ? 8 : 20)));
  for (Eigen::Index i = 0; i < nv; ++i) {
    for (int k = 0; k < 3; ++k) {
      if (binary) {
        append_raw_le(out, positions(i, k));
      } else {
        if (k > 0) out.push_back(' ');
        detail::append_double(out, positions(i, k));
      }
    }
    append_values(out, vertex_properties, i, binary);
    if (!binary) out.push_back('\n');
  }
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Triangle& t = faces[static_cast<std::size_t>(f)];
    if (binary) {
      out.push_back(static_cast<char>(3));
      for (Index v : t) append_raw_le(out, std::int32_t{v});
    } else {
      out += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]);
    }
    append_values(out, face_properties, f, binary);
    if (!binary) out.push_back('\n');
  }
  detail::write_file_atomically(path, out);
}

void write_matrix_market(const std::string& path, const Eigen::SparseMatrix<double>& A) {
  std::string body;
  std::size_t nnz = 0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it) {
      body += std::to_string(it.row() + 1);
      body.push_back(' ');
      body += std::to_string(it.col() + 1);
      body.push_back(' ');
      detail::append_double(body, it.value());
      body.push_back('\n');
      ++nnz;
    }
  }
  std::string out = "%%MatrixMarket matrix coordinate real general\n% written by ifem\n";
  out +=
      std::to_string(A.rows()) + " " + std::to_string(A.cols()) + " " + std::to_string(nnz) + "\n";
  out += body;
  detail::write_file_atomically(path, out);
}

Eigen::SparseMatrix<double> read_matrix_market(const std::string& path) {
  const std::string bytes = detail::read_file(path);
  const char* end = bytes.data() + bytes.size();
  detail::TextCursor header(path, bytes.data(), end, '\n');
  const std::string_view banner = header.token();
  if (!iequals(banner, "%%MatrixMarket")) {
    header.fail("not a Matrix Market file (missing '%%MatrixMarket' banner)");
  }
  const std::string_view object = header.token();
  const std::string_view format = header.token();
  const std::string_view field = header.token();
  const std::string_view symmetry = header.token();
  if (!iequals(object, "matrix") || !iequals(format, "coordinate")) {
    header.fail("only 'matrix coordinate' Matrix Market files are supported");
  }
  const bool pattern = iequals(field, "pattern");
  if (!pattern && !iequals(field, "real") && !iequals(field, "integer")) {
    header.fail("unsupported Matrix Market field " + detail::quoted(field));
  }
  const bool symmetric = iequals(symmetry, "symmetric");
  const bool skew = iequals(symmetry, "skew-symmetric");
  if (!symmetric && !skew && !iequals(symmetry, "general")) {
    header.fail("unsupported Matrix Market symmetry " + detail::quoted(symmetry));
  }
  header.next_line();
  detail::TextCursor c(path, header.pos(), end, '%', header.line());
  if (!c.next_content_line()) c.fail("missing size line");
  const std::int64_t rows = c.integer("row count");
  const std::int64_t cols = c.integer("column count");
  const std::int64_t nnz = c.integer("entry count");
  constexpr std::int64_t kMaxIndex = std::numeric_limits<Index>::max();
  if (rows < 0 || cols < 0 || rows > kMaxIndex || cols > kMaxIndex) {
    c.fail("matrix size out of range");
  }
  if ((symmetric || skew) && rows != cols) {
    c.fail("a " + std::string(symmetry) + " matrix must be square, the size line says " +
           std::to_string(rows) + "x" + std::to_string(cols));
  }
  // Each entry takes at least 5 characters ("1 1\n" for pattern): refuse before allocating.
  if (nnz < 0 || nnz > static_cast<std::int64_t>(c.remaining() / 4 + 1)) {
    c.fail("header declares " + std::to_string(nnz) + " entries but only " +
           std::to_string(c.remaining()) + " bytes follow (truncated?)");
  }
  // Eigen's assembly allocates one slot per row and per column: a size line far out of
  // proportion to the entries (1e9 rows for 2 entries) would allocate gigabytes for nothing.
  if (rows + cols > 16 * (nnz + 1000000)) {
    c.fail("the size line declares " + std::to_string(rows) + "x" + std::to_string(cols) + " for " +
           std::to_string(nnz) +
           " entries: too large for its entries (more than 16 rows and columns per entry "
           "beyond the first million)");
  }
  c.next_line();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(symmetric || skew ? 2 * nnz : nnz));
  for (std::int64_t k = 0; k < nnz; ++k) {
    if (!c.next_content_line()) {
      c.fail("file ends after " + std::to_string(k) + " of " + std::to_string(nnz) + " entries");
    }
    const std::int64_t i = c.integer("row index");
    const std::int64_t j = c.integer("column index");
    const double v = pattern ? 1.0 : c.number("value");
    if (i < 1 || i > rows || j < 1 || j > cols) {
      c.fail("entry (" + std::to_string(i) + ", " + std::to_string(j) + ") out of range for a " +
             std::to_string(rows) + "×" + std::to_string(cols) + " matrix");
    }
    const auto r = static_cast<Index>(i - 1);
    const auto s = static_cast<Index>(j - 1);
    triplets.emplace_back(r, s, v);
    if ((symmetric || skew) && r != s) triplets.emplace_back(s, r, skew ? -v : v);
    c.next_line();
  }
  if (c.next_content_line()) c.fail("more entries than the " + std::to_string(nnz) + " declared");
  Eigen::SparseMatrix<double> A(static_cast<Index>(rows), static_cast<Index>(cols));
  A.setFromTriplets(triplets.begin(), triplets.end());
  return A;
}

namespace {

// Writes the column-major rows × cols block at `data` as text, one line per row, through a
// fixed buffer (a 50k × 64 batch is ~60 MB of text: no string of that size is built).
void write_text_rows(const std::string& path, const double* data, Eigen::Index rows,
                     Eigen::Index cols) {
  constexpr std::size_t kLongest = 32;  // a double's shortest form is at most 24 characters
  std::vector<char> buffer(std::size_t{1} << 20);
  char* const end = buffer.data() + buffer.size();
  std::FILE* f = detail::open_temporary(path, true);
  bool ok = true;
  char* p = buffer.data();
  const auto flush = [&] {
    const auto n = static_cast<std::size_t>(p - buffer.data());
    ok = ok && std::fwrite(buffer.data(), 1, n, f) == n;
    p = buffer.data();
  };
  for (Eigen::Index i = 0; i < rows && ok; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (static_cast<std::size_t>(end - p) < kLongest) flush();
      if (j > 0) *p++ = ' ';
      p = std::to_chars(p, end, data[i + j * rows]).ptr;  // shortest round-trip form
    }
    if (p == end) flush();
    *p++ = '\n';
  }
  flush();
  detail::close_and_rename(f, ok, path);
}

}  // namespace

void write_values(const std::string& path, const Eigen::VectorXd& values) {
  write_text_rows(path, values.data(), values.size(), 1);
}

void write_rows(const std::string& path, const Eigen::MatrixXd& rows) {
  write_text_rows(path, rows.data(), rows.rows(), rows.cols());
}

Eigen::VectorXd read_values(const std::string& path) {
  const std::string bytes = detail::read_file(path);
  detail::TextCursor c(path, bytes.data(), bytes.data() + bytes.size(), '#');
  std::vector<double> values;
  while (c.next_content_line()) {
    values.push_back(c.number_any("value"));
    if (!c.at_line_end()) c.fail("more than one value on a line");
    c.next_line();
  }
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

}  // namespace ifem::io
