// Scene assembly for `ifem view` and the page around it (solvers/recipes/view_scene.h).
#include "solvers/recipes/view_scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/tokens.h"

namespace ifem::recipes {

// The page template (solvers/recipes/view_page.html), embedded by CMake (view_page_html.cpp).
extern const char* const kViewPageTemplate;

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- Geometry helpers ----

double bbox_diagonal(const Positions& p) {
  if (p.rows() == 0) return 0.0;
  return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm();
}

double mean_edge_length(const Scene& s) {
  double sum = 0.0;
  for (const Triangle& t : s.faces) {
    for (int k = 0; k < 3; ++k)
      sum += (s.positions.row(t[k]) - s.positions.row(t[(k + 1) % 3])).norm();
  }
  return s.faces.empty() ? 0.0 : sum / (3.0 * double(s.faces.size()));
}

// Area-weighted vertex normals of the faces (zero where a vertex has no face).
Eigen::MatrixX3d vertex_normals(const Scene& s) {
  Eigen::MatrixX3d n = Eigen::MatrixX3d::Zero(s.positions.rows(), 3);
  for (const Triangle& t : s.faces) {
    const Eigen::Vector3d a = s.positions.row(t[0]), b = s.positions.row(t[1]),
                          c = s.positions.row(t[2]);
    const Eigen::Vector3d fn = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n.row(t[k]) += fn.transpose();
  }
  for (Eigen::Index v = 0; v < n.rows(); ++v) {
    const double len = n.row(v).norm();
    if (len > 0.0) n.row(v) /= len;
  }
  return n;
}

void check_length(const Scene& s, const std::string& name, Eigen::Index size) {
  if (size != s.positions.rows()) {
    throw InvalidInput("view: property '" + name + "' has " + std::to_string(size) +
                       " values, the scene has " + std::to_string(s.positions.rows()) +
                       " vertices");
  }
}

// The N glyph segments of every vertex with a nonzero vector (fx, fy, fz).
void add_glyphs(Scene& s, const Eigen::MatrixX3d& vec, int symmetry) {
  const Eigen::MatrixX3d normals = vertex_normals(s);
  const double length = s.faces.empty()
                            ? 0.5 * bbox_diagonal(s.positions) / std::sqrt(double(vec.rows()))
                            : 0.4 * mean_edge_length(s);
  std::vector<Eigen::Vector3d> ends;
  for (Eigen::Index v = 0; v < vec.rows(); ++v) {
    const Eigen::Vector3d n = normals.row(v);
    Eigen::Vector3d d = vec.row(v);
    if (n.squaredNorm() > 0.0) d -= d.dot(n) * n;
    if (!(d.norm() > 0.0) || !d.allFinite()) continue;
    d.normalize();
    const Eigen::Vector3d p = s.positions.row(v);
    for (int k = 0; k < symmetry; ++k) {
      const double theta = 2.0 * kPi * k / symmetry;
      if (n.squaredNorm() == 0.0 && k != 0 && 2 * k != symmetry) continue;  // no plane to turn in
      const Eigen::Vector3d dk = std::cos(theta) * d + std::sin(theta) * n.cross(d);
      ends.push_back(p);
      ends.push_back(p + length * dk);
    }
  }
  const Eigen::Index old = s.glyph_segments.rows();
  s.glyph_segments.conservativeResize(old + Eigen::Index(ends.size()), 3);
  for (std::size_t i = 0; i < ends.size(); ++i) s.glyph_segments.row(old + i) = ends[i];
}

std::string unique_name(const Scene& s, const std::string& name) {
  auto used = [&](const std::string& n) {
    return std::any_of(s.fields.begin(), s.fields.end(),
                       [&](const SceneField& f) { return f.name == n; });
  };
  if (!used(name)) return name;
  for (int k = 2;; ++k) {
    const std::string candidate = name + " (" + std::to_string(k) + ")";
    if (!used(candidate)) return candidate;
  }
}

// ---- JSON text ----

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t w = (std::uint32_t(std::uint8_t(bytes[i])) << 16) |
                            (std::uint32_t(std::uint8_t(bytes[i + 1])) << 8) |
                            std::uint32_t(std::uint8_t(bytes[i + 2]));
    for (int k = 3; k >= 0; --k) out += table[(w >> (6 * k)) & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t w = std::uint32_t(std::uint8_t(bytes[i])) << 16;
    if (rest == 2) w |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
    out += table[(w >> 18) & 63];
    out += table[(w >> 12) & 63];
    out += rest == 2 ? table[(w >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

template <typename T>
void append_le(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (!io::detail::host_is_little_endian()) std::reverse(raw, raw + sizeof(T));
  bytes.append(raw, sizeof(T));
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '<') {
      out += "\\u003c";  // never "</script>" inside the page's data block
    } else if (u < 0x20) {
      static const char* hex = "0123456789abcdef";
      out += "\\u00";
      out += hex[u >> 4];
      out += hex[u & 15];
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::string out;
  io::detail::append_double(out, v);
  return out;
}

// Points of polylines as float32 and the number of points of each.
std::string polylines_json(const Polylines& lines) {
  std::string xyz, counts;
  for (const auto& line : lines) {
    append_le<std::uint32_t>(counts, std::uint32_t(line.size()));
    for (const Eigen::Vector3d& p : line) {
      for (int d = 0; d < 3; ++d) append_le<float>(xyz, float(p[d]));
    }
  }
  return "{\"points\":\"" + base64(xyz) + "\",\"counts\":\"" + base64(counts) + "\"}";
}

std::string field_json(const SceneField& f) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  std::string values;
  for (Eigen::Index i = 0; i < f.values.size(); ++i) {
    const double v = f.values[i];
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    append_le<float>(values, std::isfinite(v) ? float(v) : std::numeric_limits<float>::quiet_NaN());
  }
  return "{\"name\":" + json_string(f.name) + ",\"units\":" + json_string(f.units) +
         ",\"min\":" + json_number(lo) + ",\"max\":" + json_number(hi) + ",\"values\":\"" +
         base64(values) + "\"}";
}

std::string float_rows_json(const double* data, Eigen::Index n) {
  std::string bytes;
  for (Eigen::Index i = 0; i < n; ++i) append_le<float>(bytes, float(data[i]));
  return "\"" + base64(bytes) + "\"";
}

// The template with each marker (each occurring once in it) replaced, in one pass over the
// template so that no inserted text is searched for markers.
// @throws std::logic_error if a marker is missing (a bug of the template)
std::string fill_template(const std::string& page,
                          std::vector<std::pair<std::string, std::string>> fills) {
  std::vector<std::pair<std::size_t, std::size_t>> at;  // position in page, index in fills
  for (std::size_t i = 0; i < fills.size(); ++i) {
    const std::size_t pos = page.find(fills[i].first);
    if (pos == std::string::npos)
      throw std::logic_error("view page template lacks " + fills[i].first);
    at.emplace_back(pos, i);
  }
  std::sort(at.begin(), at.end());
  std::string out;
  std::size_t from = 0;
  for (const auto& [pos, i] : at) {
    out.append(page, from, pos - from);
    out += fills[i].second;
    from = pos + fills[i].first.size();
  }
  out.append(page, from, std::string::npos);
  return out;
}

// Text for an HTML element's content.
std::string html_text(const std::string& s) {
  std::string out;
  for (const char c : s) {
    out += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
  }
  return out;
}

std::string module_data_url(const std::string& path) {
  return "data:text/javascript;base64," + base64(io::detail::read_file(path));
}

}  // namespace

Scene view_scene(const io::SurfaceInput& input, const std::string& title) {
  if (input.positions.rows() == 0) throw InvalidInput("view: the input has no vertex");
  Scene s;
  s.title = title;
  s.positions = input.positions;
  s.faces = input.triangles;
  add_properties(s, input.vertex_properties);
  return s;
}

void add_field(Scene& scene, SceneField field) {
  if (field.name.empty()) throw InvalidInput("view: a field needs a name");
  check_length(scene, field.name, field.values.size());
  field.name = unique_name(scene, field.name);
  scene.fields.push_back(std::move(field));
}

void add_properties(Scene& scene, const std::vector<io::VertexProperty>& properties,
                    const std::string& prefix, int symmetry) {
  if (symmetry < 1 || symmetry > 6) {
    throw InvalidInput("view: symmetry must be in [1, 6], got " + std::to_string(symmetry));
  }
  std::map<std::string, const Eigen::VectorXd*> by_name;
  for (const io::VertexProperty& p : properties) {
    check_length(scene, p.name, p.values.size());
    by_name[p.name] = &p.values;
  }
  if (by_name.count("fx") && by_name.count("fy") && by_name.count("fz")) {
    Eigen::MatrixX3d vec(scene.positions.rows(), 3);
    vec << *by_name["fx"], *by_name["fy"], *by_name["fz"];
    add_glyphs(scene, vec, symmetry);
  }
  if (by_name.count("singularity")) {
    const Eigen::VectorXd& index = *by_name["singularity"];
    for (Eigen::Index v = 0; v < index.size(); ++v) {
      if (index[v] != 0.0 && std::isfinite(index[v])) {
        scene.singularities.push_back({scene.positions.row(v).transpose(), index[v]});
      }
    }
  }
  for (const io::VertexProperty& p : properties) add_field(scene, {prefix + p.name, "", p.values});
}

void add_polylines(Scene& scene, const std::string& name, const Polylines& lines) {
  SceneCurves c{name, {}};
  for (const auto& line : lines) {
    if (line.size() < 2) continue;
    for (const Eigen::Vector3d& p : line) {
      if (!p.allFinite()) throw InvalidInput("view: curves '" + name + "' have a non-finite point");
    }
    c.lines.push_back(line);
  }
  scene.curves.push_back(std::move(c));
}

solvers::RenderScene render_scene_of(const Scene& scene, const std::string& property) {
  solvers::RenderScene r;
  r.positions = scene.positions;
  r.triangles = scene.faces;
  const SceneField* chosen = nullptr;
  std::string names;
  for (const SceneField& f : scene.fields) {
    if (f.name == property || (property.empty() && chosen == nullptr)) chosen = &f;
    names += (names.empty() ? "" : ", ") + f.name;
  }
  if (chosen == nullptr && !property.empty()) {
    throw InvalidInput("render: no per-vertex property " + io::detail::quoted(property) +
                       " (the input has: " + (names.empty() ? "none" : names) + ")");
  }
  if (chosen != nullptr) {
    r.field = chosen->values;
    r.field_name = chosen->name;
  }
  for (const SceneCurves& c : scene.curves)
    r.curves.insert(r.curves.end(), c.lines.begin(), c.lines.end());
  r.intrinsic_edges = scene.intrinsic_edges;
  for (Eigen::Index i = 0; i + 1 < scene.glyph_segments.rows(); i += 2) {
    r.glyphs.push_back(
        {scene.glyph_segments.row(i).transpose(), scene.glyph_segments.row(i + 1).transpose()});
  }
  return r;
}

void add_intrinsic_edges(Scene& scene, const intrinsic::CorrespondenceView& st) {
  const Positions& p = st.input_positions();
  const double tolerance = 1e-9 * std::max(bbox_diagonal(scene.positions), 1e-300);
  if (p.rows() != scene.positions.rows() ||
      (p.rows() > 0 && (p - scene.positions).rowwise().norm().maxCoeff() > tolerance)) {
    throw InvalidInput("view: the intrinsic triangulation was made on another mesh (" +
                       std::to_string(p.rows()) + " input vertices, the scene has " +
                       std::to_string(scene.positions.rows()) + ", or other positions)");
  }
  scene.intrinsic_edges = st.traced_edges_3d();
}

std::string scene_json(const Scene& s) {
  std::string faces;
  for (const Triangle& t : s.faces) {
    for (int k = 0; k < 3; ++k) append_le<std::uint32_t>(faces, std::uint32_t(t[k]));
  }
  std::string out = "{\"title\":" + json_string(s.title) +
                    ",\"vertices\":" + std::to_string(s.positions.rows()) +
                    ",\"positions\":" + float_rows_json(s.positions.data(), s.positions.size()) +
                    ",\"faces\":\"" + base64(faces) + "\",\"fields\":[";
  for (std::size_t i = 0; i < s.fields.size(); ++i) out += (i ? "," : "") + field_json(s.fields[i]);
  out += "],\"curves\":[";
  for (std::size_t i = 0; i < s.curves.size(); ++i) {
    out += std::string(i ? "," : "") + "{\"name\":" + json_string(s.curves[i].name) +
           ",\"lines\":" + polylines_json(s.curves[i].lines) + "}";
  }
  out += "],\"glyphs\":" + float_rows_json(s.glyph_segments.data(), s.glyph_segments.size());
  out += ",\"singularities\":[";
  for (std::size_t i = 0; i < s.singularities.size(); ++i) {
    const SceneSingularity& q = s.singularities[i];
    out += std::string(i ? "," : "") + "[" + json_number(q.position.x()) + "," +
           json_number(q.position.y()) + "," + json_number(q.position.z()) + "," +
           json_number(q.index) + "]";
  }
  out += "],\"intrinsic_edges\":" + polylines_json(s.intrinsic_edges) + "}";
  return out;
}

std::string find_three_js(const std::string& hint) {
  std::vector<std::string> places;
  if (!hint.empty()) {
    places.push_back(hint);
  } else {
    if (const char* env = std::getenv("IFEM_THREE_DIR"); env && *env) places.push_back(env);
#ifdef IFEM_WEB_BUILD_DIR
    places.push_back(std::string(IFEM_WEB_BUILD_DIR) + "/node_modules/three");
#endif
#ifdef IFEM_WEB_INSTALL_DIR
    places.push_back(std::string(IFEM_WEB_INSTALL_DIR) + "/node_modules/three");
#endif
  }
  std::string looked;
  for (const std::string& dir : places) {
    const std::filesystem::path d(dir);
    if (std::filesystem::is_regular_file(d / "build/three.module.min.js") &&
        std::filesystem::is_regular_file(d / "examples/jsm/controls/OrbitControls.js")) {
      return dir;
    }
    looked += (looked.empty() ? "" : ", ") + dir;
  }
  throw IoError(std::string("view: three.js not found (looked in ") +
                (looked.empty() ? "no place" : looked) +
                "): run scripts/setup.sh, or `npm install --prefix DIR three@" + kThreeVersion +
                "` and pass DIR/node_modules/three (--three / three_dir= / $IFEM_THREE_DIR)");
}

std::string view_page(const Scene& scene, const std::string& three_dir) {
  const std::string three = module_data_url(three_dir + "/build/three.module.min.js");
  const std::string orbit = module_data_url(three_dir + "/examples/jsm/controls/OrbitControls.js");
  return fill_template(kViewPageTemplate,
                       {{"\"IFEM_THREE_URL\"", "\"" + three + "\""},
                        {"\"IFEM_ORBIT_URL\"", "\"" + orbit + "\""},
                        {"IFEM_TITLE", html_text(scene.title.empty() ? "ifem view" : scene.title)},
                        {"{\"IFEM_SCENE\":0}", scene_json(scene)}});
}

void write_view_page(const std::string& path, const Scene& scene, const std::string& three_dir) {
  io::detail::write_file_atomically(path, view_page(scene, three_dir));
}

}  // namespace ifem::recipes
