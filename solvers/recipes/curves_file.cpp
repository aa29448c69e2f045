// The curves file (read_curves_file) and the checks of curves against an input
// (validate_curves): the text side of solvers/recipes/curves.h, apart from the geometry in
// curves.cpp so the grammar and its messages can be read and tested on their own.
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "intrinsic/core/errors.h"
#include "intrinsic/io/detail.h"
#include "intrinsic/io/tokens.h"
#include "solvers/recipes/curves.h"

namespace ifem::solvers {
namespace {

constexpr int kMaxBezierRounds = 16;

using io::parse_whole_integer;
using io::parse_whole_real;

// The words of one line: '#' starts a comment; ':' is a word of its own even when written
// against a number ("0 1: 3 4").
std::vector<std::string> tokenize(std::string line) {
  const auto hash = line.find('#');
  if (hash != std::string::npos) line.resize(hash);
  std::string spaced;
  for (const char c : line) {
    if (c == ':') {
      spaced += " : ";
    } else {
      spaced += c;
    }
  }
  std::istringstream ss(spaced);
  std::vector<std::string> tokens;
  for (std::string t; ss >> t;) tokens.push_back(t);
  return tokens;
}

bool is_keyword(const std::string& t) {
  return t == "closed" || t == "slit" || t == "bezier" || t.rfind("bezier=", 0) == 0;
}

// Reads one line of the file into a curve; `where` is "path:line: " for messages.
class LineParser {
 public:
  LineParser(std::vector<std::string> tokens, std::string where)
      : tokens_(std::move(tokens)), where_(std::move(where)) {}

  CurveCondition parse() {
    std::size_t i = parse_keywords();
    if (i == tokens_.size()) {
      fail("expected " + std::string(curve_.slit ? "LEFT RIGHT values" : "a value") +
           " and vertex ids after the keywords");
    }
    double x = 0;
    if (tokens_[i] != ":" && !parse_whole_real(tokens_[i], x)) {
      fail(io::quoted_excerpt(tokens_[i]) +
           " is neither a keyword (closed, bezier, bezier=R, slit) nor a value (a finite "
           "number)");
    }
    std::vector<std::vector<std::string>> groups(1);
    for (; i < tokens_.size(); ++i) {
      if (tokens_[i] == ":") {
        groups.emplace_back();
      } else {
        groups.back().push_back(tokens_[i]);
      }
    }
    if (groups.size() == 1) {
      parse_constant(groups[0]);
    } else {
      parse_lists(groups);
    }
    return std::move(curve_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw IoError(where_ + what); }

  // The leading keywords; returns the index of the first word that is none.
  std::size_t parse_keywords() {
    bool closed = false, bezier = false;
    std::size_t i = 0;
    for (; i < tokens_.size(); ++i) {
      const std::string& t = tokens_[i];
      bool* seen = nullptr;
      if (t == "closed") {
        seen = &closed;
      } else if (t == "slit") {
        seen = &curve_.slit;
      } else if (t == "bezier" || t.rfind("bezier=", 0) == 0) {
        seen = &bezier;
        if (t != "bezier") curve_.bezier_rounds = parse_rounds(t);
      } else {
        break;
      }
      if (*seen) fail("keyword '" + keyword(t) + "' given twice");
      *seen = true;
      if (closed && bezier)
        fail("'closed' and 'bezier' exclude each other (a Bézier curve is open)");
    }
    if (closed) curve_.shape = intrinsic::CurveShape::kLoop;
    if (bezier) curve_.shape = intrinsic::CurveShape::kBezier;
    return i;
  }

  static std::string keyword(const std::string& t) {
    return t.rfind("bezier", 0) == 0 ? "bezier" : t;
  }

  int parse_rounds(const std::string& t) const {
    long long r = 0;
    if (!parse_whole_integer(t.substr(7), r) || r < 0 || r > kMaxBezierRounds) {
      fail(io::quoted_excerpt(t) + ": expected bezier=R with R an integer in [0, " +
           std::to_string(kMaxBezierRounds) + "] (de Casteljau rounds)");
    }
    return static_cast<int>(r);
  }

  double value(const std::string& t, const char* what) const {
    double x = 0;
    if (!parse_whole_real(t, x))
      fail(io::quoted_excerpt(t) + " is not " + what + ": expected a finite number");
    return x;
  }

  std::vector<double> values(const std::vector<std::string>& words, const char* what) const {
    std::vector<double> out;
    for (const std::string& w : words) out.push_back(value(w, what));
    return out;
  }

  void vertices(const std::vector<std::string>& words) {
    for (const std::string& w : words) {
      long long v = 0;
      if (!parse_whole_integer(w, v) || v < 0 || v > std::numeric_limits<Index>::max()) {
        fail(io::quoted_excerpt(w) + " is not a vertex id: expected an integer in [0, " +
             std::to_string(std::numeric_limits<Index>::max()) + "]" +
             (is_keyword(w) ? " (keywords come first on the line)" : ""));
      }
      curve_.vertices.push_back(static_cast<Index>(v));
    }
    if (curve_.vertices.size() < 2) {
      fail("a curve needs at least 2 vertex ids, got " + std::to_string(curve_.vertices.size()));
    }
  }

  // VALUE v0 v1 ... (slit: LEFT RIGHT v0 v1 ...)
  void parse_constant(const std::vector<std::string>& words) {
    const std::size_t nv = curve_.slit ? 2 : 1;
    if (words.size() < nv) fail("expected LEFT RIGHT values, then vertex ids");
    curve_.values = {value(words[0], curve_.slit ? "a LEFT value" : "a value")};
    if (curve_.slit) curve_.right_values = {value(words[1], "a RIGHT value")};
    vertices({words.begin() + static_cast<std::ptrdiff_t>(nv), words.end()});
  }

  // VALUES : VERTICES (slit: LEFTS : RIGHTS : VERTICES)
  void parse_lists(const std::vector<std::vector<std::string>>& groups) {
    const std::size_t want = curve_.slit ? 3 : 2;
    if (groups.size() != want) {
      fail(std::to_string(groups.size() - 1) + " ':' separators, expected " +
           std::to_string(want - 1) +
           (curve_.slit ? " (LEFTS : RIGHTS : VERTICES)" : " (VALUES : VERTICES)"));
    }
    for (std::size_t g = 0; g + 1 < groups.size(); ++g) {
      if (groups[g].empty()) fail("no values before ':'");
    }
    curve_.values = values(groups[0], curve_.slit ? "a LEFT value" : "a value");
    if (curve_.slit) curve_.right_values = values(groups[1], "a RIGHT value");
    vertices(groups.back());
    check_counts();
  }

  void check_counts() const {
    const std::size_t n = curve_.values.size();
    const bool bezier = curve_.shape == intrinsic::CurveShape::kBezier;
    const std::size_t per_point = bezier ? 2 : curve_.vertices.size();
    if (n != 1 && n != per_point) {
      fail(std::to_string(n) + " values for " + std::to_string(curve_.vertices.size()) +
           (bezier ? " control points: a Bézier curve takes 1 value (constant) or 2 (at its "
                     "ends)"
                   : " vertices: expected 1 (constant) or one per vertex"));
    }
    if (curve_.slit && curve_.right_values.size() != n) {
      fail(std::to_string(n) + " LEFT values but " + std::to_string(curve_.right_values.size()) +
           " RIGHT values: expected as many of each");
    }
  }

  std::vector<std::string> tokens_;
  std::string where_;
  CurveCondition curve_;
};

const char* shape_name(intrinsic::CurveShape s) {
  switch (s) {
    case intrinsic::CurveShape::kLoop:
      return "closed curve";
    case intrinsic::CurveShape::kBezier:
      return "Bézier curve";
    case intrinsic::CurveShape::kPath:
      break;
  }
  return "path";
}

// "" when the values of c are as CurveCondition says, else what is wrong.
std::string check_values(const CurveCondition& c) {
  const std::size_t n = c.values.size();
  const bool bezier = c.shape == intrinsic::CurveShape::kBezier;
  const std::size_t per_point = bezier ? 2 : c.vertices.size();
  if (n != 0 && n != 1 && n != per_point) {
    return std::to_string(n) + " values for a " + shape_name(c.shape) + " of " +
           std::to_string(c.vertices.size()) + " vertices: expected 1 (constant) or " +
           std::to_string(per_point) + (bezier ? " (at its ends)" : " (one per vertex)");
  }
  if (c.slit && c.right_values.size() != n) {
    return "a slit with " + std::to_string(n) + " left values and " +
           std::to_string(c.right_values.size()) + " right values: expected as many of each";
  }
  if (!c.slit && !c.right_values.empty()) return "right values on a curve that is not a slit";
  for (const std::vector<double>* list : {&c.values, &c.right_values}) {
    for (std::size_t i = 0; i < list->size(); ++i) {
      if (!std::isfinite((*list)[i])) {
        return std::string(list == &c.values ? "value " : "right value ") + std::to_string(i + 1) +
               " is not a finite number";
      }
    }
  }
  return "";
}

// "" when the vertices of c are usable on an input of n vertices, else what is wrong.
std::string check_vertices(const CurveCondition& c, Index n) {
  const std::vector<Index>& v = c.vertices;
  if (v.size() < 2) {
    return "a curve needs at least 2 vertices, got " + std::to_string(v.size());
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] < 0 || v[i] >= n) {
      return "vertex " + std::to_string(v[i]) + " out of range [0, " + std::to_string(n) +
             ") (the input has " + std::to_string(n) + " vertices)";
    }
  }
  for (std::size_t i = 0; i + 1 < v.size(); ++i) {
    if (v[i] == v[i + 1]) {
      return "vertex " + std::to_string(v[i]) + " twice in a row (positions " +
             std::to_string(i + 1) + " and " + std::to_string(i + 2) + ")";
    }
  }
  if (c.shape == intrinsic::CurveShape::kLoop && v.front() == v.back()) {
    return "a closed curve's last vertex " + std::to_string(v.back()) +
           " is its first (the loop closes by itself: do not repeat it)";
  }
  return "";
}

}  // namespace

std::vector<CurveCondition> read_curves_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory");
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::vector<CurveCondition> curves;
  std::string line;
  long lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::vector<std::string> tokens = tokenize(line);
    if (tokens.empty()) continue;  // blank or comment
    const std::string origin = path + ":" + std::to_string(lineno);
    curves.push_back(LineParser(std::move(tokens), origin + ": ").parse());
    curves.back().origin = origin;
  }
  if (in.bad()) throw IoError(path + ": read error after line " + std::to_string(lineno));
  if (curves.empty()) {
    throw IoError(path + ": no curve in the file (every line is blank or a comment)");
  }
  return curves;
}

std::string curve_line(const CurveCondition& c) {
  const std::string name = c.origin.empty() ? std::string("curve") : c.origin;
  if (c.values.empty()) {
    throw InvalidInput(name +
                       ": a curve without values cannot be written to a curves file (every "
                       "line starts with its values)");
  }
  std::string line;
  const auto word = [&line](const std::string& w) {
    if (!line.empty()) line += ' ';
    line += w;
  };
  const auto number = [&line](double x) {
    if (!line.empty()) line += ' ';
    const std::size_t start = line.size();
    io::detail::append_double(line, x);
    // a value reads as a number, not a vertex id: integral values get ".0" ("1.0", not "1")
    if (line.find_first_not_of("-0123456789", start) == std::string::npos) line += ".0";
  };
  if (c.shape == intrinsic::CurveShape::kLoop) word("closed");
  if (c.shape == intrinsic::CurveShape::kBezier) word("bezier=" + std::to_string(c.bezier_rounds));
  if (c.slit) word("slit");
  std::vector<const std::vector<double>*> lists = {&c.values};
  if (c.slit) lists.push_back(&c.right_values);
  if (c.values.size() == 1) {
    for (const auto* l : lists) number(l->at(0));
  } else {
    for (const auto* l : lists) {
      for (const double x : *l) number(x);
      word(":");
    }
  }
  for (const Index v : c.vertices) word(std::to_string(v));
  return line;
}

void write_curves_file(const std::string& path, const std::vector<CurveCondition>& curves) {
  std::string text;
  for (const CurveCondition& c : curves) text += curve_line(c) + "\n";
  io::detail::write_file_atomically(path, text);
}

void validate_curves(const std::vector<CurveCondition>& curves, Index n_vertices,
                     bool need_values) {
  for (std::size_t i = 0; i < curves.size(); ++i) {
    const CurveCondition& c = curves[i];
    const std::string name = c.origin.empty() ? "curve #" + std::to_string(i) : c.origin;
    std::string what = check_vertices(c, n_vertices);
    if (what.empty()) what = check_values(c);
    if (what.empty() && c.shape == intrinsic::CurveShape::kBezier &&
        (c.bezier_rounds < 0 || c.bezier_rounds > kMaxBezierRounds)) {
      what = "Bézier rounds " + std::to_string(c.bezier_rounds) + " out of range [0, " +
             std::to_string(kMaxBezierRounds) + "]";
    }
    if (what.empty() && need_values && c.values.empty()) {
      what = "the curve carries no value (a boundary-value problem needs one on every curve)";
    }
    if (!what.empty()) throw InvalidInput(name + ": " + what);
  }
}

}  // namespace ifem::solvers
