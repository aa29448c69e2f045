// Private helpers shared by the mesh readers and writers (intrinsic/io_*.cpp): whole-file
// reading, a zero-copy text cursor with line numbers, a bounds-checked byte reader, error
// helpers and atomic file writing. Not installed as part of the public API.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/progress.h"
#include "intrinsic/io/surface_input.h"

namespace ifem::io::detail {

/// Reads a whole file into memory, reporting stage "read" (bytes read over the file's size) to
/// `on_progress` when it is given and not empty.
/// @throws IoError if the file is missing, a directory, or unreadable
std::string read_file(const std::string& path, const ProgressCallback* on_progress = nullptr);

/// Writes `bytes` to `path.tmp`, then renames it to `path`; removes the tmp file on failure.
/// @throws IoError if any step fails
void write_file_atomically(const std::string& path, const std::string& bytes);

/// Opens `path`.tmp for writing (binary or text); throws IoError naming it when that fails.
/// Writers that stream with fprintf write there, then call close_and_rename() to stay atomic.
std::FILE* open_temporary(const std::string& path, bool binary);

/// Finishes a file written through `f` from open_temporary(path): closes it and renames it to
/// `path`, or removes it and throws IoError when `ok` is false, a write failed, or the rename
/// fails.
void close_and_rename(std::FILE* f, bool ok, const std::string& path);

/// Throws IoError "<path>, line <line>: <problem>".
[[noreturn]] void fail_line(const std::string& path, std::size_t line, const std::string& problem);
/// Throws IoError "<path>, byte offset <offset>: <problem>".
[[noreturn]] void fail_offset(const std::string& path, std::size_t offset,
                              const std::string& problem);
/// Throws IoError "<path>: <problem>".
[[noreturn]] void fail_file(const std::string& path, const std::string& problem);

/// A token for an error message: quoted, cut to 40 characters.
std::string quoted(std::string_view token);

/// Appends the shortest decimal text that reads back to exactly `v`.
void append_double(std::string& out, double v);

inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Forward-only cursor over a text buffer that knows its 1-based line number. Tokens are runs
/// of non-blank characters; `comment` (e.g. '#') starts a comment that runs to the line end.
class TextCursor {
 public:
  TextCursor(const std::string& path, const char* begin, const char* end, char comment = '#',
             std::size_t first_line = 1)
      : path_(path),
        begin_(begin),
        p_(begin),
        end_(end),
        comment_(comment),
        first_line_(first_line),
        line_(first_line) {}

  bool eof() const { return p_ == end_; }
  std::size_t line() const { return line_; }
  const char* pos() const { return p_; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  const std::string& path() const { return path_; }

  void skip_blanks() {
    while (p_ != end_ && is_blank(*p_)) ++p_;
  }
  /// Skips blanks and newlines (counting lines), and comments when a comment char is set.
  void skip_whitespace() {
    while (p_ != end_) {
      const char c = *p_;
      if (c == '\n') {
        ++line_;
        ++p_;
      } else if (is_blank(c)) {
        ++p_;
      } else if (c == comment_) {
        skip_to_line_end();
      } else {
        break;
      }
    }
  }
  /// True when the current line has no more tokens (newline, comment or end of file).
  bool at_line_end() {
    skip_blanks();
    return p_ == end_ || *p_ == '\n' || *p_ == comment_;
  }
  /// Moves to the start of the next line.
  void next_line() {
    const void* nl = std::memchr(p_, '\n', static_cast<std::size_t>(end_ - p_));
    if (nl == nullptr) {
      p_ = end_;
    } else {
      p_ = static_cast<const char*>(nl) + 1;
      ++line_;
    }
  }
  /// Moves to the first token of the next line that has one; false at end of file.
  bool next_content_line() {
    while (at_line_end()) {
      if (p_ == end_) return false;
      next_line();
    }
    return true;
  }
  /// The next token on the current line (empty at the line end).
  std::string_view token() {
    if (at_line_end()) return {};
    const char* b = p_;
    while (p_ != end_ && !ends_token(p_)) ++p_;
    return {b, static_cast<std::size_t>(p_ - b)};
  }
  /// Parses a number on the current line; NaN and inf are accepted.
  double number_any(const char* what);
  /// Parses a finite number on the current line.
  /// @throws IoError on a missing, malformed or NaN/inf value
  double number(const char* what);
  /// Parses an integer on the current line.
  std::int64_t integer(const char* what);

  /// Throws IoError at the current line (at the end of a file that ends with a newline: the
  /// last line, not the empty one after it).
  [[noreturn]] void fail(const std::string& problem) const {
    const bool after_last_newline = p_ == end_ && p_ != begin_ && *(p_ - 1) == '\n';
    fail_line(path_, after_last_newline && line_ > first_line_ ? line_ - 1 : line_, problem);
  }

  bool ends_token(const char* q) const {
    return q == end_ || is_blank(*q) || *q == '\n' || *q == comment_;
  }

 private:
  void skip_to_line_end() {
    const void* nl = std::memchr(p_, '\n', static_cast<std::size_t>(end_ - p_));
    p_ = nl == nullptr ? end_ : static_cast<const char*>(nl);
  }
  std::string_view peek_token() const;
  const std::string& path_;
  const char* begin_;
  const char* p_;
  const char* end_;
  char comment_;
  std::size_t first_line_;
  std::size_t line_;
};

/// Collects polygons and remembers the largest index seen and where. Each polygon is stored as
/// its fan (v0, vk, vk+1), contiguous in `triangles` with one `triangle_polygon` id: an exact
/// encoding of its corners while positions may still be unknown (OBJ `v` lines can follow `f`
/// lines). read_surface() then calls triangulate_polygons(), which replaces each fan.
class PolygonSink {
 public:
  explicit PolygonSink(SurfaceInput& out) : out_(out) {}
  /// Adds a polygon of n ≥ 3 zero-based indices (each ≥ 0); `where` is a line or byte offset.
  void add(const Index* v, std::size_t n, std::size_t where) {
    const Index polygon = out_.n_polygons++;
    if (n > 3) ++out_.n_non_triangles;
    for (std::size_t k = 0; k < n; ++k) {
      if (v[k] > max_index_) {
        max_index_ = v[k];
        max_where_ = where;
      }
    }
    for (std::size_t k = 1; k + 1 < n; ++k) {
      out_.triangles.push_back({v[0], v[k], v[k + 1]});
      out_.triangle_polygon.push_back(polygon);
    }
  }
  /// Adds one triangle as its own polygon.
  void add_triangle(Index a, Index b, Index c, std::size_t where) {
    const Index t[3] = {a, b, c};
    add(t, 3, where);
  }
  Index max_index() const { return max_index_; }
  std::size_t max_where() const { return max_where_; }

 private:
  SurfaceInput& out_;
  Index max_index_ = -1;
  std::size_t max_where_ = 0;
};

/// Throws "face index out of range" at the sink's recorded place when an index ≥ n_vertices;
/// `index_base` is added to the index in the message (1 for OBJ).
void check_max_index(const std::string& path, const PolygonSink& sink, Index n_vertices,
                     bool binary, int index_base = 0);

/// Re-triangulates every polygon of more than 3 corners that the sink stored as a fan, once all
/// positions and all polygon sides are known, in place (same triangle count and
/// triangle_polygon): no new diagonal coincides with a side of any polygon or with a diagonal
/// chosen before (so no triangle repeats and no edge gains faces the polygons did not imply),
/// short diagonals preferred; polygons that repeat a vertex keep their fan. Linear time:
/// polygons of up to 32 corners are ear-clipped (best ear first: no collision, then a convex
/// ear holding no other corner, then the shortest diagonal), larger ones become a fan from one
/// of a few apexes. Indices must be in range (the readers check them first).
void triangulate_polygons(SurfaceInput& s);

/// Moves flat xyz triples into `out.positions` (and normals when given).
void set_positions(SurfaceInput& out, const std::vector<double>& xyz);
void set_normals(SurfaceInput& out, const std::vector<double>& nxyz);

/// Host byte order.
inline bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// Format readers: `bytes` is the whole file.
/// (OBJ: reports stage "parse", the bytes parsed over the file's, to `on_progress` if given.)
SurfaceInput read_obj(const std::string& path, const std::string& bytes,
                      const ProgressCallback* on_progress = nullptr);
SurfaceInput read_off(const std::string& path, const std::string& bytes);
SurfaceInput read_ply(const std::string& path, const std::string& bytes);
SurfaceInput read_stl(const std::string& path, const std::string& bytes);
SurfaceInput read_xyz(const std::string& path, const std::string& bytes);

}  // namespace ifem::io::detail
