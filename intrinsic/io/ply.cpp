// PLY reader: ASCII, binary little-endian and binary big-endian; any scalar type for vertex
// and face properties, any integer type for list counts and indices, `face` and `tristrips`
// elements, other elements skipped. Counts in the header are checked against the file size before
// anything is allocated.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>
#include <vector>

#include "intrinsic/io/detail.h"

namespace ifem::io::detail {
namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class PlyFormat { kAscii, kBinaryLe, kBinaryBe };

bool parse_type(std::string_view s, PlyType& t) {
  struct Named {
    const char* name;
    PlyType type;
  };
  static const Named kTypes[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& named : kTypes) {
    if (s == named.name) {
      t = named.type;
      return true;
    }
  }
  return false;
}

std::size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 1;
}

bool is_integer(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
  std::size_t body_line = 0;
};

PlyHeader parse_header(const std::string& path, const std::string& bytes) {
  PlyHeader h;
  const char* begin = bytes.data();
  TextCursor c(path, begin, begin + bytes.size(), '\n');
  if (c.token() != "ply") c.fail("not a PLY file (the first line must be 'ply')");
  c.next_line();
  bool have_format = false;
  for (;;) {
    if (c.eof()) c.fail("PLY header ends without 'end_header'");
    const std::string_view keyword = c.token();
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") {
      c.next_line();
      continue;
    }
    if (keyword == "end_header") {
      c.next_line();
      h.body_offset = static_cast<std::size_t>(c.pos() - begin);
      h.body_line = c.line();
      break;
    }
    if (keyword == "format") {
      const std::string_view f = c.token();
      if (f == "ascii") {
        h.format = PlyFormat::kAscii;
      } else if (f == "binary_little_endian") {
        h.format = PlyFormat::kBinaryLe;
      } else if (f == "binary_big_endian") {
        h.format = PlyFormat::kBinaryBe;
      } else {
        c.fail("unknown PLY format " + quoted(f));
      }
      have_format = true;
    } else if (keyword == "element") {
      PlyElement e;
      e.name = std::string(c.token());
      if (e.name.empty()) c.fail("element without a name");
      const std::int64_t count = c.integer("element count");
      if (count < 0) c.fail("negative element count");
      e.count = static_cast<std::uint64_t>(count);
      e.line = c.line();
      h.elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (h.elements.empty()) c.fail("property before any element");
      PlyProperty p;
      std::string_view type = c.token();
      if (type == "list") {
        p.is_list = true;
        const std::string_view count_type = c.token();
        if (!parse_type(count_type, p.count_type)) {
          c.fail("unknown list count type " + quoted(count_type));
        }
        if (!is_integer(p.count_type)) c.fail("list count type must be an integer type");
        type = c.token();
      }
      if (!parse_type(type, p.type)) c.fail("unknown property type " + quoted(type));
      p.name = std::string(c.token());
      if (p.name.empty()) c.fail("property without a name");
      h.elements.back().properties.push_back(std::move(p));
    } else {
      c.fail("unknown PLY header keyword " + quoted(keyword) + " (missing 'end_header'?)");
    }
    c.next_line();
  }
  if (!have_format) fail_line(path, 2, "PLY header has no 'format' line");
  return h;
}

/// Loads a T stored in the file's byte order.
template <class T>
T load(const unsigned char* p, bool swap) {
  unsigned char buf[sizeof(T)];
  if (swap) {
    for (std::size_t k = 0; k < sizeof(T); ++k) buf[k] = p[sizeof(T) - 1 - k];
  } else {
    std::memcpy(buf, p, sizeof(T));
  }
  T v;
  std::memcpy(&v, buf, sizeof(T));
  return v;
}

/// Reads binary PLY values; positions are absolute byte offsets in the file.
class BinarySource {
 public:
  BinarySource(const std::string& path, const std::string& bytes, std::size_t offset, bool swap)
      : path_(path),
        data_(reinterpret_cast<const unsigned char*>(bytes.data())),
        size_(bytes.size()),
        pos_(offset),
        swap_(swap) {}
  static constexpr bool kBinary = true;
  std::size_t where() const { return pos_; }
  std::size_t remaining() const { return size_ - pos_; }
  void begin_item(const char* element, std::uint64_t i) {
    element_ = element;
    item_ = i;
  }
  [[noreturn]] void fail(std::size_t where, const std::string& problem) const {
    fail_offset(path_, where, problem);
  }
  double scalar(PlyType t) {
    need(type_size(t));
    const unsigned char* p = data_ + pos_;
    pos_ += type_size(t);
    switch (t) {
      case PlyType::kInt8:
        return load<std::int8_t>(p, false);
      case PlyType::kUint8:
        return load<std::uint8_t>(p, false);
      case PlyType::kInt16:
        return load<std::int16_t>(p, swap_);
      case PlyType::kUint16:
        return load<std::uint16_t>(p, swap_);
      case PlyType::kInt32:
        return load<std::int32_t>(p, swap_);
      case PlyType::kUint32:
        return load<std::uint32_t>(p, swap_);
      case PlyType::kFloat32:
        return load<float>(p, swap_);
      case PlyType::kFloat64:
        return load<double>(p, swap_);
    }
    return 0;
  }
  std::int64_t integer(PlyType t) {
    if (!is_integer(t)) {
      const std::size_t at = pos_;
      const double v = scalar(t);
      if (!(v == std::floor(v) && std::abs(v) < 9e15)) fail(at, "non-integer list value");
      return static_cast<std::int64_t>(v);
    }
    return static_cast<std::int64_t>(scalar(t));
  }
  void skip(PlyType t) {
    need(type_size(t));
    pos_ += type_size(t);
  }
  void check_list(std::int64_t n, PlyType item, std::size_t at) const {
    if (static_cast<std::uint64_t>(n) > remaining() / type_size(item)) {
      fail(at, "truncated: list of " + std::to_string(n) + " items in element '" + element_ +
                   "' #" + std::to_string(item_) + " runs past the end of the file");
    }
  }

 private:
  void need(std::size_t n) const {
    if (remaining() < n) {
      fail(pos_, "truncated: the file ends inside element '" + std::string(element_) + "' #" +
                     std::to_string(item_));
    }
  }
  const std::string& path_;
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_;
  bool swap_;
  const char* element_ = "";
  std::uint64_t item_ = 0;
};

/// Reads ASCII PLY values as whitespace-separated tokens; positions are line numbers.
class AsciiSource {
 public:
  AsciiSource(const std::string& path, const std::string& bytes, std::size_t offset,
              std::size_t line)
      : c_(path, bytes.data() + offset, bytes.data() + bytes.size(), '\n', line) {}
  static constexpr bool kBinary = false;
  std::size_t where() {
    c_.skip_whitespace();
    return c_.line();
  }
  void begin_item(const char* element, std::uint64_t i) {
    element_ = element;
    item_ = i;
  }
  [[noreturn]] void fail(std::size_t where, const std::string& problem) const {
    fail_line(c_.path(), where, problem);
  }
  double scalar(PlyType t) {
    next();
    if (is_integer(t)) return static_cast<double>(c_.integer("integer property"));
    return c_.number_any("property value");
  }
  std::int64_t integer(PlyType t) {
    next();
    if (is_integer(t)) return c_.integer("list value");
    const double v = c_.number_any("list value");
    if (!(v == std::floor(v) && std::abs(v) < 9e15)) c_.fail("non-integer list value");
    return static_cast<std::int64_t>(v);
  }
  void skip(PlyType) {
    next();
    c_.token();
  }
  void check_list(std::int64_t n, PlyType, std::size_t at) const {
    // Each item takes at least two characters.
    if (static_cast<std::uint64_t>(n) > static_cast<std::uint64_t>(c_.remaining()) / 2 + 1) {
      fail(at, "list of " + std::to_string(n) + " items in element '" + element_ + "' #" +
                   std::to_string(item_) + " runs past the end of the file");
    }
  }

 private:
  void next() {
    c_.skip_whitespace();
    if (c_.eof()) {
      c_.fail("truncated: the file ends inside element '" + std::string(element_) + "' #" +
              std::to_string(item_));
    }
  }
  TextCursor c_;
  const char* element_ = "";
  std::uint64_t item_ = 0;
};

enum class Kind { kVertex, kFace, kTristrips, kOther };

/// Where a vertex scalar goes: 0–2 position, 3–5 normal, 6+k extra property k, -1 nowhere.
struct VertexLayout {
  std::vector<int> target;
  std::vector<std::string> extra_names;
  bool has_normals = false;
};

VertexLayout vertex_layout(const std::string& path, const PlyElement& e) {
  VertexLayout layout;
  static const char* const kNames[6] = {"x", "y", "z", "nx", "ny", "nz"};
  int found[6] = {-1, -1, -1, -1, -1, -1};
  for (std::size_t p = 0; p < e.properties.size(); ++p) {
    if (e.properties[p].is_list) continue;
    for (int k = 0; k < 6; ++k) {
      if (e.properties[p].name == kNames[k] && found[k] < 0) found[k] = static_cast<int>(p);
    }
  }
  if (found[0] < 0 || found[1] < 0 || found[2] < 0) {
    fail_line(path, e.line, "the vertex element has no x, y and z properties");
  }
  layout.has_normals = found[3] >= 0 && found[4] >= 0 && found[5] >= 0;
  layout.target.assign(e.properties.size(), -1);
  for (std::size_t p = 0; p < e.properties.size(); ++p) {
    if (e.properties[p].is_list) continue;
    int t = -1;
    for (int k = 0; k < 6; ++k) {
      if (found[k] == static_cast<int>(p) && (k < 3 || layout.has_normals)) t = k;
    }
    if (t < 0) {
      t = 6 + static_cast<int>(layout.extra_names.size());
      layout.extra_names.push_back(e.properties[p].name);
    }
    layout.target[p] = t;
  }
  return layout;
}

/// Decodes one triangle strip (−1 restarts) into triangles, alternating orientation and
/// dropping the degenerate connector triangles.
void add_strip(PolygonSink& sink, const std::vector<Index>& strip, std::size_t where) {
  std::size_t start = 0;
  for (std::size_t k = 0; k <= strip.size(); ++k) {
    if (k < strip.size() && strip[k] != -1) continue;
    for (std::size_t j = start; j + 2 < k; ++j) {
      Index a = strip[j];
      Index b = strip[j + 1];
      const Index c = strip[j + 2];
      if ((j - start) % 2 == 1) std::swap(a, b);
      if (a == b || b == c || a == c) continue;
      sink.add_triangle(a, b, c, where);
    }
    start = k + 1;
  }
}

/// What the reader does with an element: vertices, faces, triangle strips or nothing.
Kind element_kind(const PlyElement& e) {
  if (e.name == "vertex") return Kind::kVertex;
  if (e.name == "face") return Kind::kFace;
  if (e.name == "tristrips") return Kind::kTristrips;
  return Kind::kOther;
}

/// The property index of the vertex_indices (or vertex_index) list of a face or strip element.
int index_list_property(const std::string& path, const PlyElement& e) {
  int index_list = -1;
  for (std::size_t p = 0; p < e.properties.size(); ++p) {
    const auto& name = e.properties[p].name;
    if (e.properties[p].is_list && (name == "vertex_indices" || name == "vertex_index")) {
      index_list = static_cast<int>(p);
    }
  }
  if (index_list < 0) {
    fail_line(path, e.line, "element '" + e.name + "' has no vertex_indices list");
  }
  return index_list;
}

/// Reads the body of a PLY file element by element from a Source (AsciiSource or BinarySource)
/// into vertex arrays and a PolygonSink; finish() moves them into the SurfaceInput.
template <class Source>
class BodyReader {
 public:
  BodyReader(const std::string& path, Source& src, SurfaceInput& out)
      : path_(path), src_(src), out_(out), sink_(out) {}

  /// Reads all items of element e (vertex, face, tristrips; others are skipped).
  void read_element(const PlyElement& e) {
    const Kind kind = element_kind(e);
    if (kind == Kind::kVertex && n_vertices_ >= 0) {
      fail_line(path_, e.line, "more than one vertex element");
    }
    layout_ = VertexLayout();
    int index_list = -1;
    if (kind == Kind::kVertex) {
      begin_vertices(e);
    } else if (kind != Kind::kOther) {
      index_list = index_list_property(path_, e);
      if (kind == Kind::kFace) {
        out_.triangles.reserve(out_.triangles.size() + e.count);
        out_.triangle_polygon.reserve(out_.triangle_polygon.size() + e.count);
        begin_face_values(e);
      }
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      src_.begin_item(e.name.c_str(), i);
      const std::size_t item_where = src_.where();
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        if (!prop.is_list) {
          read_scalar(kind, prop, p, i);
        } else {
          read_list(e, kind, prop, static_cast<int>(p) == index_list, i);
        }
      }
      if (kind == Kind::kVertex) check_finite(i, item_where);
    }
  }

  /// Moves positions, normals and extra vertex properties into the output; checks the indices.
  void finish() {
    set_positions(out_, xyz_);
    out_.normals.resize(0, 3);
    if (has_normals_) set_normals(out_, nxyz_);
    for (std::size_t k = 0; k < extra_.size(); ++k) {
      VertexProperty property;
      property.name = extra_names_[k];
      property.values = Eigen::Map<const Eigen::VectorXd>(
          extra_[k].data(), static_cast<Eigen::Index>(extra_[k].size()));
      out_.vertex_properties.push_back(std::move(property));
    }
    for (std::size_t k = 0; k < face_extra_.size(); ++k) {
      VertexProperty property;
      property.name = face_names_[k];
      property.values = Eigen::Map<const Eigen::VectorXd>(
          face_extra_[k].data(), static_cast<Eigen::Index>(face_extra_[k].size()));
      out_.face_properties.push_back(std::move(property));
    }
    check_max_index(path_, sink_, std::max<Index>(n_vertices_, 0), Source::kBinary);
  }

 private:
  /// Lays out the vertex element's properties and sizes the vertex arrays.
  void begin_vertices(const PlyElement& e) {
    layout_ = vertex_layout(path_, e);
    const auto n = static_cast<std::size_t>(e.count);  // checked against the file size
    xyz_.resize(3 * n);
    if (layout_.has_normals) nxyz_.resize(3 * n);
    extra_.assign(layout_.extra_names.size(), std::vector<double>(n));
    extra_names_ = layout_.extra_names;
    has_normals_ = layout_.has_normals;
    n_vertices_ = static_cast<Index>(e.count);
  }

  /// The slots of a face element's scalar properties (face_slot_; a name seen in an earlier face
  /// element continues its values), their arrays reserved.
  void begin_face_values(const PlyElement& e) {
    face_slot_.assign(e.properties.size(), -1);
    for (std::size_t p = 0; p < e.properties.size(); ++p) {
      if (e.properties[p].is_list) continue;
      const auto it = std::find(face_names_.begin(), face_names_.end(), e.properties[p].name);
      face_slot_[p] = static_cast<int>(it - face_names_.begin());
      if (it == face_names_.end()) {
        face_names_.push_back(e.properties[p].name);
        face_extra_.emplace_back();
      }
      face_extra_[face_slot_[p]].reserve(face_extra_[face_slot_[p]].size() + e.count);
    }
  }

  /// Reads (or skips) scalar property p of item i into its vertex or face array slot.
  void read_scalar(Kind kind, const PlyProperty& prop, std::size_t p, std::uint64_t i) {
    if (kind == Kind::kFace && face_slot_[p] >= 0) {
      face_extra_[face_slot_[p]].push_back(src_.scalar(prop.type));
      return;
    }
    if (kind != Kind::kVertex || layout_.target[p] < 0) {
      src_.skip(prop.type);
      return;
    }
    const double v = src_.scalar(prop.type);
    const int t = layout_.target[p];
    if (t < 3) {
      xyz_[3 * i + t] = v;
    } else if (t < 6) {
      nxyz_[3 * i + t - 3] = v;
    } else {
      extra_[t - 6][i] = v;
    }
  }

  /// Reads a list property of item i: skipped unless it is the index list, which becomes a
  /// polygon (face) or a strip of triangles (tristrips).
  void read_list(const PlyElement& e, Kind kind, const PlyProperty& prop, bool is_index_list,
                 std::uint64_t i) {
    const std::size_t list_where = src_.where();
    const std::int64_t n = src_.integer(prop.count_type);
    if (n < 0) src_.fail(list_where, "negative list length " + std::to_string(n));
    src_.check_list(n, prop.type, list_where);
    if (!is_index_list) {
      for (std::int64_t k = 0; k < n; ++k) src_.skip(prop.type);
      return;
    }
    list_.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      const std::size_t at = src_.where();
      const std::int64_t v = src_.integer(prop.type);
      const bool restart = kind == Kind::kTristrips && v == -1;
      if ((v < 0 && !restart) || v > std::numeric_limits<Index>::max()) {
        src_.fail(at, "face index " + std::to_string(v) + " out of range in element '" + e.name +
                          "' #" + std::to_string(i));
      }
      list_.push_back(static_cast<Index>(v));
    }
    if (kind == Kind::kTristrips) {
      add_strip(sink_, list_, list_where);
    } else {
      if (n < 3) {
        src_.fail(list_where, "face #" + std::to_string(i) + " has " + std::to_string(n) +
                                  " vertices (at least 3 needed)");
      }
      sink_.add(list_.data(), list_.size(), list_where);
    }
  }

  /// Fails on a NaN or infinite coordinate of vertex i.
  void check_finite(std::uint64_t i, std::size_t item_where) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(xyz_[3 * i + k])) {
        src_.fail(item_where, "NaN or infinite coordinate in vertex #" + std::to_string(i));
      }
    }
  }

  const std::string& path_;
  Source& src_;
  SurfaceInput& out_;
  PolygonSink sink_;
  VertexLayout layout_;  // of the element being read (empty unless it is the vertex element)
  std::vector<double> xyz_;
  std::vector<double> nxyz_;
  std::vector<std::vector<double>> extra_;
  std::vector<std::string> extra_names_;
  std::vector<Index> list_;     // index list of the current face or strip, reused
  std::vector<int> face_slot_;  // per property of the face element being read: its face array
  std::vector<std::vector<double>> face_extra_;
  std::vector<std::string> face_names_;
  bool has_normals_ = false;
  Index n_vertices_ = -1;
};

/// Reads all elements of the body into out.
template <class Source>
void read_body(const std::string& path, const PlyHeader& h, Source& src, SurfaceInput& out) {
  BodyReader<Source> reader(path, src, out);
  for (const PlyElement& e : h.elements) reader.read_element(e);
  reader.finish();
}

}  // namespace

SurfaceInput read_ply(const std::string& path, const std::string& bytes) {
  const PlyHeader h = parse_header(path, bytes);
  const std::size_t body = bytes.size() - h.body_offset;
  const PlyElement* vertex = nullptr;
  // Refuse element counts the file cannot hold before allocating: each binary element needs
  // at least its fixed-size bytes, each ASCII element at least two characters per property.
  std::uint64_t needed = 0;
  for (const PlyElement& e : h.elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.count == 0) continue;
    std::uint64_t min_size = 0;
    for (const PlyProperty& p : e.properties) {
      min_size += h.format == PlyFormat::kAscii ? 2 : type_size(p.is_list ? p.count_type : p.type);
    }
    if (min_size == 0) fail_line(path, e.line, "element '" + e.name + "' has no properties");
    const std::uint64_t room = body + 1 > needed ? body + 1 - needed : 0;
    if (e.count > room / min_size) {
      const std::string problem = "header declares " + std::to_string(e.count) + " '" + e.name +
                                  "' elements but the file has only " + std::to_string(body) +
                                  " bytes after the header (truncated?)";
      if (h.format == PlyFormat::kAscii) fail_line(path, e.line, problem);
      fail_offset(path, h.body_offset, problem);
    }
    needed += e.count * min_size;
  }
  if (vertex == nullptr) fail_file(path, "PLY file has no 'vertex' element");
  if (vertex->count > static_cast<std::uint64_t>(std::numeric_limits<Index>::max())) {
    fail_line(path, vertex->line, "too many vertices for 32-bit indices");
  }
  SurfaceInput out;
  if (h.format == PlyFormat::kAscii) {
    out.format = "ply-ascii";
    AsciiSource src(path, bytes, h.body_offset, h.body_line);
    read_body(path, h, src, out);
  } else {
    const bool file_le = h.format == PlyFormat::kBinaryLe;
    out.format = file_le ? "ply-binary-le" : "ply-binary-be";
    BinarySource src(path, bytes, h.body_offset, file_le != host_is_little_endian());
    read_body(path, h, src, out);
  }
  return out;
}

}  // namespace ifem::io::detail
