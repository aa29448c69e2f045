// Saving and restoring a NormalCoordinateTriangulation: the "ifem-integer 1" text format.
//
// One record per line, fields separated by spaces, doubles printed with %.17g (exact round
// trip), ids 0-based, -1 = none; lines starting with '#' are comments:
//
//   ifem-integer 1
//   input_vertices NV        then NV lines "x y z"
//   input_faces NF           then NF lines "a b c origin": face f of input() (the tails of its
//                            halfedges 3f, 3f+1, 3f+2) and the index of the given face it came
//                            from (input_face_origin())
//   input_halfedges          then 3·NF lines "twin length" for input() halfedge 3f+s
//   input_edges NE           then NE lines "h": input() edge e is the edge of halfedge h
//   intrinsic NVI NFI        intrinsic vertex and face counts (NVI ≥ NV)
//   halfedges                then 3·NFI lines "tail twin length roundabout"
//   edges NE                 then NE lines "h n": edge e is the edge of halfedge h, normal
//                            coordinate n (−1: along an input edge)
//   spokes                   then NVI lines "k e_1 at_1 … e_k at_k m s_1 … s_m": vertex v's k
//                            spokes (input edge, position along it) and, for a vertex with
//                            several fans of faces, the m entries of its fan table (m = 0 else)
//   end
//
// Input vertices are intrinsic vertices 0..NV−1.
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "intrinsic/core/errors.h"
#include "intrinsic/integer/normal_coordinates.h"
#include "intrinsic/io/detail.h"

namespace ifem::intrinsic {

void NormalCoordinateTriangulation::save(const std::string& path) const {
  std::FILE* f = io::detail::open_temporary(path, false);
  std::fprintf(f, "ifem-integer 1\n# intrinsic triangulation with normal coordinates\n");
  std::fprintf(f, "input_vertices %ld\n", long(positions_.rows()));
  for (Eigen::Index v = 0; v < positions_.rows(); ++v) {
    std::fprintf(f, "%.17g %.17g %.17g\n", positions_(v, 0), positions_(v, 1), positions_(v, 2));
  }
  std::fprintf(f, "input_faces %d\n", int(input_.n_faces()));
  for (Index t = 0; t < input_.n_faces(); ++t) {
    std::fprintf(f, "%d %d %d %d\n", int(input_.tail(3 * t)), int(input_.tail(3 * t + 1)),
                 int(input_.tail(3 * t + 2)), int(face_origin_[t]));
  }
  std::fprintf(f, "input_halfedges\n");
  for (Index h = 0; h < input_.n_halfedges(); ++h) {
    std::fprintf(f, "%d %.17g\n", int(input_.twin(h)), input_.halfedge_length(h));
  }
  std::fprintf(f, "input_edges %d\n", int(input_.n_edges()));
  for (Index e = 0; e < input_.n_edges(); ++e)
    std::fprintf(f, "%d\n", int(input_.edge_halfedge(e)));
  std::fprintf(f, "intrinsic %d %d\nhalfedges\n", int(tri_.n_vertices()), int(tri_.n_faces()));
  for (Index h = 0; h < tri_.n_halfedges(); ++h) {
    std::fprintf(f, "%d %d %.17g %d\n", int(tri_.tail(h)), int(tri_.twin(h)),
                 tri_.halfedge_length(h), r_[h]);
  }
  std::fprintf(f, "edges %d\n", int(tri_.n_edges()));
  for (Index e = 0; e < tri_.n_edges(); ++e) {
    std::fprintf(f, "%d %d\n", int(tri_.edge_halfedge(e)), n_[e]);
  }
  std::fprintf(f, "spokes\n");
  for (Index v = 0; v < tri_.n_vertices(); ++v) {
    std::fprintf(f, "%zu", spokes_[v].size());
    for (const InputSpoke& s : spokes_[v]) std::fprintf(f, " %d %.17g", int(s.input_edge), s.at);
    const std::vector<int> none;
    const std::vector<int>& fans = v < Index(fans_.size()) ? fans_[v] : none;
    std::fprintf(f, " %zu", fans.size());
    for (const int s : fans) std::fprintf(f, " %d", s);
    std::fprintf(f, "\n");
  }
  std::fprintf(f, "end\n");
  io::detail::close_and_rename(f, true, path);
}

namespace {

// Record reader: one record per line, blank lines and '#' comments skipped; every error is an
// IoError naming the file and the line.
class Records {
 public:
  explicit Records(const std::string& path)
      : path_(path),
        bytes_(io::detail::read_file(path)),
        c_(path_, bytes_.data(), bytes_.data() + bytes_.size()) {}

  void next(const std::string& what) {
    if (started_) c_.next_line();
    started_ = true;
    if (!c_.next_content_line()) fail("unexpected end of file, expected " + what);
  }
  std::string word() { return std::string(c_.token()); }
  long integer(const std::string& what) { return long(c_.integer(what.c_str())); }
  double number(const std::string& what) { return c_.number(what.c_str()); }
  // An integer in [lo, hi].
  long in_range(const std::string& what, long lo, long hi) {
    const long x = integer(what);
    if (x < lo || x > hi) {
      fail(what + " " + std::to_string(x) + " out of range [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]");
    }
    return x;
  }
  void end_of_record(const std::string& what) {
    if (!c_.at_line_end()) fail("expected " + what + ", got more on the line");
  }
  // The next record is `word`, then (when asked) one count in [0, max] that the rest of the
  // file can hold at min_bytes per record.
  long keyword(const std::string& word, long max = -1, std::size_t min_bytes = 2) {
    next("'" + word + "'");
    const std::string w = this->word();
    if (w != word) fail("expected '" + word + "', got '" + w + "'");
    if (max < 0) return 0;
    const long n = in_range("the count of '" + word + "'", 0, max);
    expect_records(n, min_bytes, word);
    return n;
  }
  void expect_records(long count, std::size_t min_bytes, const std::string& what) const {
    if (count > static_cast<long>(c_.remaining() / min_bytes + 1)) {
      fail("the file declares " + std::to_string(count) + " " + what +
           " records but is too short to hold them");
    }
  }
  [[noreturn]] void fail(const std::string& msg) const { c_.fail(msg); }

 private:
  std::string path_;
  std::string bytes_;
  io::detail::TextCursor c_;
  bool started_ = false;
};

constexpr long kMaxIndex = std::numeric_limits<Index>::max() / 3;

void read_header(Records& r) {
  r.next("the header 'ifem-integer 1'");
  const std::string w = r.word();
  if (w == "ifem-signpost") {
    r.fail("this is a signpost file (ifem-signpost), not normal coordinates (ifem-integer)");
  }
  if (w != "ifem-integer") r.fail("not an ifem-integer file (first word '" + w + "')");
  const long version = r.integer("the version");
  if (version != 1) r.fail("unsupported version " + std::to_string(version) + " (this reads 1)");
  r.end_of_record("'ifem-integer 1'");
}

// A triangulation's gluing as read: tails, twins, lengths per halfedge, edges' halfedges.
struct Gluing {
  long n_vertices = 0;
  std::vector<Index> tail, twin, edge_halfedge;
  std::vector<double> length;
  IntrinsicTriangulation build(Records& r, const char* what) {
    try {
      IntrinsicTriangulation t = IntrinsicTriangulation::from_gluing(
          std::move(tail), std::move(twin), length, Index(n_vertices));
      t.renumber_edges(edge_halfedge);
      return t;
    } catch (const InvalidInput& e) {
      r.fail(std::string(what) + ": " + e.what());
    }
  }
};

// input_vertices, input_faces, input_halfedges, input_edges.
Gluing read_input(Records& r, Positions& x, std::vector<Index>& origin) {
  Gluing g;
  g.n_vertices = r.keyword("input_vertices", kMaxIndex, 6);
  x.resize(g.n_vertices, 3);
  for (long v = 0; v < g.n_vertices; ++v) {
    r.next("'x y z'");
    for (int k = 0; k < 3; ++k) x(v, k) = r.number("coordinate of input vertex");
    r.end_of_record("'x y z'");
  }
  const long nf = r.keyword("input_faces", kMaxIndex, 8);
  g.tail.resize(3 * nf);
  origin.resize(nf);
  for (long f = 0; f < nf; ++f) {
    r.next("'a b c origin'");
    for (int k = 0; k < 3; ++k)
      g.tail[3 * f + k] = Index(r.in_range("vertex id", 0, g.n_vertices - 1));
    origin[f] = Index(r.in_range("origin face", 0, kMaxIndex));
    r.end_of_record("'a b c origin'");
  }
  r.keyword("input_halfedges");
  g.twin.resize(3 * nf);
  g.length.resize(3 * nf);
  for (long h = 0; h < 3 * nf; ++h) {
    r.next("'twin length'");
    const long tw = r.in_range("twin", -1, 3 * nf - 1);
    g.twin[h] = tw < 0 ? kInvalidIndex : Index(tw);
    g.length[h] = r.number("length");
    r.end_of_record("'twin length'");
  }
  const long ne = r.keyword("input_edges", 3 * nf, 2);
  g.edge_halfedge.resize(ne);
  for (long e = 0; e < ne; ++e) {
    r.next("'h'");
    g.edge_halfedge[e] = Index(r.in_range("halfedge id", 0, 3 * nf - 1));
    r.end_of_record("'h'");
  }
  return g;
}

// intrinsic, halfedges (with roundabouts), edges (with normal coordinates).
Gluing read_intrinsic(Records& r, long nv_input, std::vector<int>& round, std::vector<int>& n) {
  Gluing g;
  r.keyword("intrinsic");
  g.n_vertices = r.in_range("the intrinsic vertex count", nv_input, kMaxIndex);
  const long nf = r.in_range("the intrinsic face count", 0, kMaxIndex);
  r.end_of_record("'intrinsic NVI NFI'");
  r.keyword("halfedges");
  r.expect_records(3 * nf, 8, "halfedges");
  g.tail.resize(3 * nf);
  g.twin.resize(3 * nf);
  g.length.resize(3 * nf);
  round.resize(3 * nf);
  for (long h = 0; h < 3 * nf; ++h) {
    r.next("'tail twin length roundabout'");
    g.tail[h] = Index(r.in_range("tail", 0, g.n_vertices - 1));
    const long tw = r.in_range("twin", -1, 3 * nf - 1);
    g.twin[h] = tw < 0 ? kInvalidIndex : Index(tw);
    g.length[h] = r.number("length");
    round[h] = int(r.in_range("roundabout", 0, std::numeric_limits<int>::max()));
    r.end_of_record("'tail twin length roundabout'");
  }
  const long ne = r.keyword("edges", 3 * nf, 4);
  g.edge_halfedge.resize(ne);
  n.resize(ne);
  for (long e = 0; e < ne; ++e) {
    r.next("'h n'");
    g.edge_halfedge[e] = Index(r.in_range("halfedge id", 0, 3 * nf - 1));
    n[e] = int(r.in_range("normal coordinate", -1, std::numeric_limits<int>::max()));
    r.end_of_record("'h n'");
  }
  return g;
}

// One vertex's spokes and fan table.
void read_spokes(Records& r, long n_input_edges, std::vector<InputSpoke>& spokes,
                 std::vector<int>& fans) {
  r.next("'k e_1 at_1 ... m s_1 ...'");
  const long k = r.in_range("spoke count", 0, 2 * n_input_edges);
  spokes.resize(k);
  for (InputSpoke& s : spokes) {
    s.input_edge = Index(r.in_range("spoke input edge", 0, n_input_edges - 1));
    s.at = r.number("spoke position");
    if (!(s.at >= 0.0 && s.at <= 1.0)) r.fail("spoke position outside [0, 1]");
  }
  const long m = r.in_range("fan table size", 0, k + 1);
  fans.resize(m);
  for (int& s : fans) s = int(r.in_range("fan start", 0, k));
  for (long i = 1; i < m; ++i) {
    if (fans[i] <= fans[i - 1]) r.fail("fan starts not increasing");
  }
  if (m > 0 && (m < 3 || fans[0] != 0 || fans[m - 1] != k)) {
    r.fail("a fan table lists 0, the start of every further fan, then the spoke count");
  }
  r.end_of_record("the spokes of a vertex");
}

}  // namespace

NormalCoordinateTriangulation NormalCoordinateTriangulation::load(const std::string& path) {
  Records r(path);
  read_header(r);
  Positions x;
  std::vector<Index> origin;
  Gluing in = read_input(r, x, origin);
  std::vector<Triangle> faces(in.tail.size() / 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    faces[f] = {in.tail[3 * f], in.tail[3 * f + 1], in.tail[3 * f + 2]};
  }
  std::vector<int> round, n;
  Gluing gl = read_intrinsic(r, in.n_vertices, round, n);
  IntrinsicTriangulation input = in.build(r, "input triangulation");
  IntrinsicTriangulation tri = gl.build(r, "intrinsic triangulation");
  r.keyword("spokes");
  r.expect_records(tri.n_vertices(), 4, "vertex spokes");
  std::vector<std::vector<InputSpoke>> spokes(tri.n_vertices());
  std::vector<std::vector<int>> fans(tri.n_vertices());
  for (Index v = 0; v < tri.n_vertices(); ++v) read_spokes(r, input.n_edges(), spokes[v], fans[v]);
  r.keyword("end");
  // the input's faces are already clean (oriented, manifold): rebuilding from them gives a
  // valid object, whose every field is then replaced by the saved one
  std::optional<NormalCoordinateTriangulation> nc;
  try {
    nc.emplace(faces, x);
  } catch (const Error& e) {
    throw IoError(path + ": input faces: " + e.what());
  }
  nc->input_ = std::move(input);
  nc->tri_ = std::move(tri);
  nc->face_origin_ = std::move(origin);
  nc->n_ = std::move(n);
  nc->r_ = std::move(round);
  nc->spokes_ = std::move(spokes);
  nc->fans_ = std::move(fans);
  try {
    nc->validate();
  } catch (const InvalidInput& e) {
    throw IoError(path + ": inconsistent normal coordinates: " + e.what());
  }
  return std::move(*nc);
}

}  // namespace ifem::intrinsic
