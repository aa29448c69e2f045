// The small text formats of the recipes (text_formats.h): one reader per format, errors at
// FILE:line.
#include "solvers/recipes/text_formats.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/tokens.h"

namespace ifem::recipes {
namespace {

using io::parse_whole_integer;
using io::parse_whole_real;

// Calls line(where, tokens, text) for every line with tokens; where is "FILE:N".
template <class Line>
void for_each_line(const std::string& path, Line&& line) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::string text;
  for (long n = 1; std::getline(in, text); ++n) {
    const std::vector<std::string> tokens = io::line_tokens(text);
    if (tokens.empty()) continue;
    line(path + ":" + std::to_string(n), n, tokens, text);
  }
}

bool vertex_id(const std::string& t, Index& v) {
  long long x = 0;
  if (!parse_whole_integer(t, x) || x < 0 || x > std::numeric_limits<Index>::max()) return false;
  v = static_cast<Index>(x);
  return true;
}

std::string range(Index n) { return "[0, " + std::to_string(n) + ")"; }

}  // namespace

std::vector<std::string> split_fields(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (s.empty() || s.back() == sep) parts.emplace_back();
  return parts;
}

std::vector<ListedVertex> read_vertex_list(const std::string& path) {
  std::vector<ListedVertex> ids;
  for_each_line(path, [&](const std::string& where, long n, const std::vector<std::string>& tokens,
                          const std::string& text) {
    Index v = 0;
    if (tokens.size() != 1 || !vertex_id(tokens[0], v)) {
      throw IoError(where + ": expected one vertex id (an integer ≥ 0) per line, got " +
                    io::quoted_excerpt(text));
    }
    ids.push_back({v, n});
  });
  if (ids.empty()) throw InvalidInput(path + ": no vertex id (one per line)");
  return ids;
}

std::vector<Index> checked_vertex_ids(const std::string& path,
                                      const std::vector<ListedVertex>& listed, Index n_vertices) {
  std::vector<Index> ids;
  ids.reserve(listed.size());
  for (const ListedVertex& l : listed) {
    if (l.vertex < 0 || l.vertex >= n_vertices) {
      throw InvalidInput(path + ":" + std::to_string(l.line) + ": vertex " +
                         std::to_string(l.vertex) + " out of range " + range(n_vertices) +
                         " (the input has " + std::to_string(n_vertices) + " vertices)");
    }
    ids.push_back(l.vertex);
  }
  return ids;
}

DirichletValues read_dirichlet_file(const std::string& path, Index n_vertices) {
  std::vector<Index> vertices;
  std::vector<double> values;
  for_each_line(path, [&](const std::string& where, long, const std::vector<std::string>& tokens,
                          const std::string& text) {
    long long v = 0;
    double x = 0;
    if (tokens.size() != 2 || !parse_whole_integer(tokens[0], v) ||
        !parse_whole_real(tokens[1], x)) {
      throw IoError(where + ": expected 'vertex value' (a vertex id and a finite number), got " +
                    io::quoted_excerpt(text));
    }
    if (v < 0 || v >= n_vertices) {
      throw InvalidInput(where + ": vertex " + tokens[0] + " out of range " + range(n_vertices));
    }
    vertices.push_back(static_cast<Index>(v));
    values.push_back(x);
  });
  DirichletValues d;
  d.vertices = std::move(vertices);
  d.values = Eigen::Map<const Eigen::VectorXd>(values.data(), Eigen::Index(values.size()));
  return d;
}

std::vector<solvers::InputDirection> read_constraints_file(const std::string& path) {
  std::vector<solvers::InputDirection> out;
  for_each_line(path, [&](const std::string& where, long, const std::vector<std::string>& tokens,
                          const std::string& text) {
    solvers::InputDirection d;
    d.origin = where;
    bool ok = tokens.size() == 4 && vertex_id(tokens[0], d.vertex);
    for (int k = 0; ok && k < 3; ++k) ok = parse_whole_real(tokens[k + 1], d.direction[k]);
    if (!ok) {
      throw IoError(where + ": expected 'VERTEX X Y Z' (a vertex id ≥ 0 and a direction), got " +
                    io::quoted_excerpt(text.substr(0, text.find('#'))));
    }
    out.push_back(d);
  });
  if (out.empty()) {
    throw IoError(path +
                  ": no direction in the file (every line is blank or a comment; expected "
                  "'VERTEX X Y Z' lines)");
  }
  return out;
}

std::string parse_point_token(const std::string& token, GivenPoint& p) {
  p = GivenPoint{};
  p.token = "'" + token + "'";
  if (token.rfind("face:", 0) != 0) {
    if (!vertex_id(token, p.vertex)) {
      return io::quoted_excerpt(token) +
             " is not a point: expected a vertex id (an integer ≥ 0) or face:F:u:v";
    }
    return "";
  }
  const std::vector<std::string> f = split_fields(token, ':');
  double u = 0, v = 0;
  if (f.size() != 4 || !vertex_id(f[1], p.face) || !parse_whole_real(f[2], u) ||
      !parse_whole_real(f[3], v)) {
    p.face = kInvalidIndex;
    return io::quoted_excerpt(token) +
           " is not a point: expected face:F:u:v (a face point: F a 0-based face index, u and "
           "v finite numbers) or a vertex id";
  }
  if (u < 0.0 || v < 0.0 || u + v > 1.0 + 1e-12) {
    p.face = kInvalidIndex;
    return io::quoted_excerpt(token) +
           ": the barycentric coordinates (1 − u − v, u, v) must be ≥ 0 (u, v ≥ 0, u + v ≤ 1)";
  }
  p.bary = {std::max(0.0, 1.0 - u - v), u, v};
  return "";
}

std::string repeated_point(const GivenCurve& c) {
  const std::size_t n = c.points.size();
  for (std::size_t k = 0; n >= 2 && k < (c.closed ? n : n - 1); ++k) {
    const GivenPoint& a = c.points[k];
    const GivenPoint& b = c.points[(k + 1) % n];
    if (a.same_as(b)) {
      return "points " + std::to_string(k + 1) + " and " + std::to_string((k + 1) % n + 1) +
             " are the same point " + a.token + " (consecutive points must differ)";
    }
  }
  return "";
}

std::vector<GivenCurve> read_network_file(const std::string& path, bool pin_loops) {
  std::vector<GivenCurve> curves;
  for_each_line(path, [&](const std::string& where, long, const std::vector<std::string>& tokens,
                          const std::string& text) {
    if ((tokens[0] != "path" && tokens[0] != "loop") || tokens.size() < 3) {
      throw IoError(where + ": expected 'path P0 P1 ...' or 'loop P0 P1 ...' (at least two " +
                    "points), got " + io::quoted_excerpt(text));
    }
    GivenCurve c;
    c.origin = where;
    c.closed = tokens[0] == "loop";
    c.pin = !c.closed || pin_loops;
    for (std::size_t k = 1; k < tokens.size(); ++k) {
      GivenPoint p;
      const std::string problem = parse_point_token(tokens[k], p);
      if (!problem.empty()) throw IoError(where + ": " + problem);
      c.points.push_back(std::move(p));
    }
    const std::string repeated = repeated_point(c);
    if (!repeated.empty()) throw IoError(where + ": " + repeated);
    curves.push_back(std::move(c));
  });
  if (curves.empty()) throw IoError(path + ": no curves (expected 'path ...' or 'loop ...' lines)");
  return curves;
}

}  // namespace ifem::recipes
