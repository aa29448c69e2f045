// Start paths along the descent of a guide potential (guided_path.h).
#include "intrinsic/geodesic/guided_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "intrinsic/core/errors.h"
#include "intrinsic/core/triangle_formulas.h"

namespace ifem::intrinsic {
namespace {

using T = IntrinsicTriangulation;

// A corner position below this fraction of a side counts as reaching the corner.
constexpr double kCornerSnap = 1e-7;

struct Layout {
  Eigen::Vector2d p[3];
};

Layout layout_of(const T& tri, Index f) {
  Layout l;
  face_layout(tri, f, l.p);
  return l;
}

// −∇φ in face f's layout (φ linear on the face); zero on a degenerate face.
Eigen::Vector2d descent(const T& tri, const Eigen::VectorXd& phi, Index f, const Layout& l) {
  const double area2 = cross2(l.p[1] - l.p[0], l.p[2] - l.p[0]);
  if (!(area2 > 0.0)) return Eigen::Vector2d::Zero();
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d e = l.p[(i + 2) % 3] - l.p[(i + 1) % 3];
    g += phi[tri.tail(3 * f + i)] * Eigen::Vector2d(-e.y(), e.x());
  }
  return -g / area2;
}

PathStep step_along(const T& tri, Index h, bool along) {
  const Index e = tri.edge(h);
  return {e, along ? tri.edge_halfedge(e) == h : tri.edge_halfedge(e) != h};
}

// The side of face f from corner i to corner j (nothing when i == j).
void face_step(const T& tri, Index f, int i, int j, std::vector<PathStep>* out) {
  if (i == j) return;
  if (j == (i + 1) % 3) {
    out->push_back(step_along(tri, 3 * f + i, true));
  } else {
    out->push_back(step_along(tri, 3 * f + j, false));
  }
}

// The two sides of the strip of faces a curve crosses between two vertices.
struct Strip {
  std::vector<PathStep> left, right;
  void to_corner(const T& tri, Index f, int lc, int rc, int k) {
    face_step(tri, f, lc, k, &left);
    face_step(tri, f, rc, k, &right);
  }
};

// How a curve (the descent curve, or an exact geodesic) runs between two vertices it touches:
// it leaves corner `corner` of face `face`, crosses the sides `exits` in order (each a halfedge
// of the face the curve is in, leaving it into its twin's face) and ends at corner `end` of the
// last face.
struct StripCrossing {
  Index face = kInvalidIndex;
  int corner = 0;
  std::vector<Index> exits;
  int end = 0;
};

// The two edge paths along the sides of a crossed strip: no vertex lies between either of them
// and the curve, so both are in its class.
Strip strip_sides(const T& tri, const StripCrossing& c) {
  Strip s;
  Index f = c.face;
  int lc = c.corner, rc = c.corner;
  for (const Index h : c.exits) {
    const int j = static_cast<int>(T::side(h));
    face_step(tri, f, lc, (j + 1) % 3, &s.left);
    face_step(tri, f, rc, j, &s.right);
    const Index ht = tri.twin(h);
    f = T::face(ht), lc = static_cast<int>(T::side(ht)), rc = (lc + 1) % 3;
  }
  s.to_corner(tri, f, lc, rc, c.end);
  return s;
}

double steps_length(const T& tri, const std::vector<PathStep>& s) {
  double l = 0.0;
  for (const PathStep& x : s) l += tri.length(x.edge);
  return l;
}

// The side of face f (other than `skip`) through which the ray x + s·d leaves it, and the
// parameter t along that side (from its tail); false when none is found (degenerate face).
bool exit_side(const Layout& l, const Eigen::Vector2d& x, const Eigen::Vector2d& d, int skip,
               int* side, double* t) {
  double best = std::numeric_limits<double>::infinity();
  for (int j = 0; j < 3; ++j) {
    if (j == skip) continue;
    const Eigen::Vector2d e = l.p[(j + 1) % 3] - l.p[j];
    const double den = cross2(d, e);
    if (!(cross2(e, d) < 0.0)) continue;  // not leaving through this side
    const Eigen::Vector2d w = l.p[j] - x;
    const double s = cross2(w, e) / den;
    if (s < -1e-12 * e.norm() || s >= best) continue;
    best = s;
    *side = j;
    *t = std::clamp(cross2(w, d) / den, 0.0, 1.0);
  }
  return std::isfinite(best);
}

// Where a leg of the descent from vertex v leaves v: the outgoing halfedge whose corner holds
// −∇φ, or kInvalidIndex.
Index leaving_corner(const T& tri, const Eigen::VectorXd& phi, Index v, Eigen::Vector2d* dir) {
  const Index h0 = tri.vertex_halfedge(v);
  Index x = h0;
  for (Index guard = 0; x != kInvalidIndex && guard <= tri.n_halfedges(); ++guard) {
    const Index f = T::face(x);
    const int c = static_cast<int>(T::side(x));
    const Layout l = layout_of(tri, f);
    const Eigen::Vector2d d = descent(tri, phi, f, l);
    if (d.squaredNorm() > 0.0 && cross2(l.p[(c + 1) % 3] - l.p[c], d) >= 0.0 &&
        cross2(d, l.p[(c + 2) % 3] - l.p[c]) >= 0.0) {
      *dir = d;
      return x;
    }
    x = tri.twin(T::prev(x));
    if (x == h0) break;
  }
  return kInvalidIndex;
}

// The steepest descending edge at v (an outgoing halfedge, or the incoming boundary side
// reversed: *along false), or kInvalidIndex when no neighbour is lower.
Index steepest_edge(const T& tri, const Eigen::VectorXd& phi, Index v, bool* along) {
  Index best = kInvalidIndex;
  double slope = 0.0;
  auto consider = [&](Index h, bool fwd, Index u) {
    const double s = (phi[v] - phi[u]) / tri.length(tri.edge(h));
    if (s > slope) slope = s, best = h, *along = fwd;
  };
  const Index h0 = tri.vertex_halfedge(v);
  Index x = h0;
  for (Index guard = 0; x != kInvalidIndex && guard <= tri.n_halfedges(); ++guard) {
    consider(x, true, tri.head(x));
    const Index n = tri.twin(T::prev(x));
    if (n == kInvalidIndex) consider(T::prev(x), false, tri.tail(T::prev(x)));
    if (n == h0 || n == kInvalidIndex) break;
    x = n;
  }
  return best;
}

// Follows the descent from face f, left at corner c (point x, direction d), until it reaches a
// vertex; records the crossing in *cross and returns that vertex, or kInvalidIndex when it
// stalls.
Index follow(const T& tri, const Eigen::VectorXd& phi, Index b, Index f, int c, Eigen::Vector2d x,
             Eigen::Vector2d d, Index* budget, StripCrossing* cross) {
  cross->face = f, cross->corner = c, cross->exits.clear();
  for (int in = -1; (*budget)-- > 0;) {
    for (int k = 0; k < 3; ++k) {
      if (tri.tail(3 * f + k) != b) continue;
      cross->end = k;
      return b;
    }
    const Layout l = layout_of(tri, f);
    int j = -1;
    double t = 0.0;
    if (!exit_side(l, x, d, in, &j, &t)) return kInvalidIndex;
    const Index h = 3 * f + j, ht = tri.twin(h);
    if (t < kCornerSnap || t > 1.0 - kCornerSnap || ht == kInvalidIndex) {
      // a corner, or the boundary: to the side's corner the curve reaches / the lower one
      const bool to_tail = ht == kInvalidIndex ? phi[tri.tail(h)] <= phi[tri.head(h)] : t < 0.5;
      cross->end = to_tail ? j : (j + 1) % 3;
      return tri.tail(3 * f + cross->end);
    }
    cross->exits.push_back(h);
    const Index g = T::face(ht);
    const int s_in = static_cast<int>(T::side(ht));
    const Layout lg = layout_of(tri, g);
    x = lg.p[(s_in + 1) % 3] + t * (lg.p[s_in] - lg.p[(s_in + 1) % 3]);
    d = descent(tri, phi, g, lg);
    f = g, in = s_in;
    const int lc = s_in, rc = (s_in + 1) % 3;
    if (!(cross2(lg.p[rc] - lg.p[lc], d) > 0.0)) {  // a valley along this edge: to its lower end
      cross->end = phi[tri.tail(3 * g + lc)] <= phi[tri.tail(3 * g + rc)] ? lc : rc;
      return tri.tail(3 * g + cross->end);
    }
  }
  return kInvalidIndex;
}

// Appends the side of the strip `cross` describes that `pick` chooses to *steps.
void append_side(const T& tri, const StripCrossing& cross, StripSide pick,
                 std::vector<PathStep>* steps) {
  const Strip strip = strip_sides(tri, cross);
  const bool left = pick == StripSide::kShorter
                        ? steps_length(tri, strip.left) <= steps_length(tri, strip.right)
                        : pick == StripSide::kLeft;
  const std::vector<PathStep>& side = left ? strip.left : strip.right;
  steps->insert(steps->end(), side.begin(), side.end());
}

// One leg of the descent from vertex v to the next vertex it reaches (appended to *steps);
// kInvalidIndex when it stalls.
Index descend_from(const T& tri, const Eigen::VectorXd& phi, Index v, Index b, StripSide pick,
                   Index* budget, std::vector<PathStep>* steps) {
  Eigen::Vector2d d;
  const Index x = leaving_corner(tri, phi, v, &d);
  if (x == kInvalidIndex) {
    bool along = true;
    const Index h = steepest_edge(tri, phi, v, &along);
    if (h == kInvalidIndex) return kInvalidIndex;
    steps->push_back(step_along(tri, h, along));
    return along ? tri.head(h) : tri.tail(h);
  }
  const Index f = T::face(x);
  const int c = static_cast<int>(T::side(x));
  const Layout l = layout_of(tri, f);
  StripCrossing cross;
  const Index w = follow(tri, phi, b, f, c, l.p[c], d, budget, &cross);
  if (w != kInvalidIndex) append_side(tri, cross, pick, steps);
  return w;
}

void check_vertex(const T& tri, Index v, const char* name, const char* fn = "descent_edge_path") {
  if (v < 0 || v >= tri.n_vertices()) {
    throw InvalidInput(std::string(fn) + ": " + name + " = " + std::to_string(v) +
                       " is out of range [0, " + std::to_string(tri.n_vertices()) + ")");
  }
}

}  // namespace

const char* to_string(StartPath start) {
  switch (start) {
    case StartPath::kDijkstra:
      return "dijkstra";
    case StartPath::kGuided:
      return "guided";
    case StartPath::kBest:
      return "best";
  }
  return "?";
}

StartPath start_path_from(const std::string& name) {
  for (StartPath s : {StartPath::kBest, StartPath::kGuided, StartPath::kDijkstra}) {
    if (name == to_string(s)) return s;
  }
  throw InvalidInput("'" + name + "': expected 'best', 'guided' or 'dijkstra'");
}

EdgePath descent_edge_path(const T& tri, Index a, Index b, const Eigen::VectorXd& guide,
                           StripSide side) {
  check_vertex(tri, a, "a");
  check_vertex(tri, b, "b");
  if (guide.size() != tri.n_vertices()) {
    throw InvalidInput("descent_edge_path: the guide has " + std::to_string(guide.size()) +
                       " values, the triangulation " + std::to_string(tri.n_vertices()) +
                       " vertices");
  }
  if (a == b) throw InvalidInput("descent_edge_path: a == b (" + std::to_string(a) + ")");
  EdgePath path;
  std::vector<char> seen(static_cast<std::size_t>(tri.n_vertices()), 0);
  Index budget = 4 * tri.n_faces() + 100;
  for (Index v = a; v != b;) {
    seen[v] = 1;
    if (!std::isfinite(guide[v])) return shortest_edge_path(tri, a, b);
    v = descend_from(tri, guide, v, b, side, &budget, &path.steps);
    if (v == kInvalidIndex || seen[v]) return shortest_edge_path(tri, a, b);
  }
  return path;
}

namespace {

// A point of an exact path as a vertex (a corner with coordinate ≈ 1), else kInvalidIndex.
Index point_vertex(const T& tri, const SurfacePoint& p) {
  Eigen::Index k = 0;
  if (p.bary.maxCoeff(&k) < 1.0 - 1e-9) return kInvalidIndex;
  return tri.tail(3 * p.face + static_cast<Index>(k));
}

// The edge a crossing point lies on (its face side with coordinate ≈ 0).
Index point_edge(const T& tri, const SurfacePoint& p) {
  Eigen::Index k = 0;
  p.bary.minCoeff(&k);
  return tri.edge(3 * p.face + (static_cast<Index>(k) + 1) % 3);
}

// The crossing of the strip from vertex u over the edges `edges` to vertex w; false when the
// edges do not form such a strip.
bool crossing_of(const T& tri, Index u, const std::vector<Index>& edges, Index w,
                 StripCrossing* cross) {
  const Index h0 = tri.vertex_halfedge(u);
  Index x = h0, entry = kInvalidIndex;
  for (Index guard = 0; x != kInvalidIndex && guard <= tri.n_halfedges(); ++guard) {
    if (tri.edge(T::next(x)) == edges[0]) {
      entry = x;
      break;
    }
    x = tri.twin(T::prev(x));
    if (x == h0) break;
  }
  if (entry == kInvalidIndex) return false;
  cross->face = T::face(entry), cross->corner = static_cast<int>(T::side(entry));
  cross->exits.clear();
  Index f = cross->face, in = kInvalidIndex;
  for (const Index e : edges) {
    Index exit = kInvalidIndex;
    for (int j = 0; j < 3 && exit == kInvalidIndex; ++j) {
      if (3 * f + j != in && tri.edge(3 * f + j) == e) exit = 3 * f + j;
    }
    if (exit == kInvalidIndex || tri.twin(exit) == kInvalidIndex) return false;
    cross->exits.push_back(exit);
    in = tri.twin(exit), f = T::face(in);
  }
  cross->end = static_cast<int>(T::side(T::prev(in)));
  return tri.tail(T::prev(in)) == w;
}

// The shortest edge from u to w as a step; false when they are not adjacent.
bool edge_step(const T& tri, Index u, Index w, PathStep* step) {
  double best = std::numeric_limits<double>::infinity();
  const Index h0 = tri.vertex_halfedge(u);
  Index x = h0;
  for (Index guard = 0; x != kInvalidIndex && guard <= tri.n_halfedges(); ++guard) {
    if (tri.head(x) == w && tri.length(tri.edge(x)) < best) {
      best = tri.length(tri.edge(x)), *step = step_along(tri, x, true);
    }
    const Index p = T::prev(x);
    if (tri.tail(p) == w && tri.twin(p) == kInvalidIndex && tri.length(tri.edge(p)) < best) {
      best = tri.length(tri.edge(p)), *step = step_along(tri, p, false);
    }
    x = tri.twin(p);
    if (x == h0) break;
  }
  return std::isfinite(best);
}

// The edge path along the strips of `points` (an exact path, vertex to vertex); empty when the
// points do not describe one.
EdgePath strips_of_points(const T& tri, const std::vector<SurfacePoint>& points, StripSide side) {
  EdgePath path;
  Index u = kInvalidIndex;
  std::vector<Index> edges;
  for (const SurfacePoint& p : points) {
    const Index v = point_vertex(tri, p);
    if (v == kInvalidIndex) {
      edges.push_back(point_edge(tri, p));
      continue;
    }
    if (u == kInvalidIndex || v == u) {
      u = v, edges.clear();
      continue;
    }
    if (edges.empty()) {
      PathStep s{};
      if (!edge_step(tri, u, v, &s)) return {};
      path.steps.push_back(s);
    } else {
      StripCrossing cross;
      if (!crossing_of(tri, u, edges, v, &cross)) return {};
      append_side(tri, cross, side, &path.steps);
    }
    u = v, edges.clear();
  }
  return path;
}

}  // namespace

EdgePath exact_edge_path(const T& tri, Index a, Index b, const ExactDistance& from_b,
                         StripSide side) {
  check_vertex(tri, a, "a", "exact_edge_path");
  check_vertex(tri, b, "b", "exact_edge_path");
  if (from_b.tri == nullptr || from_b.tri->n_halfedges() != tri.n_halfedges() ||
      from_b.distance.size() != tri.n_vertices()) {
    throw InvalidInput("exact_edge_path: the exact distance was computed on another triangulation");
  }
  if (a == b) throw InvalidInput("exact_edge_path: a == b (" + std::to_string(a) + ")");
  const std::vector<SurfacePoint> points = from_b.path_to_source(a);
  if (points.empty() || point_vertex(tri, points.back()) != b) {
    return shortest_edge_path(tri, a, b);  // b unreachable (throws), or b is not its source
  }
  EdgePath path = strips_of_points(tri, points, side);
  return path.steps.empty() ? shortest_edge_path(tri, a, b) : path;
}

}  // namespace ifem::intrinsic

namespace ifem::intrinsic {
namespace {

// The link of vertex c from u to w: from outgoing halfedge o_u (c → u) to o_w (c → w), turning
// clockwise (cw) or counter-clockwise around c; false at the boundary or after a whole turn.
bool around_vertex(const T& tri, Index o_u, Index o_w, bool cw, std::vector<PathStep>* route) {
  Index x = o_u;
  for (Index guard = 0; guard <= tri.n_halfedges(); ++guard) {
    if (x == o_w) return !route->empty();
    if (cw) {
      const Index t = tri.twin(x);
      if (t == kInvalidIndex) return false;
      route->push_back(step_along(tri, T::prev(t), false));
      x = T::next(t);
    } else {
      route->push_back(step_along(tri, T::next(x), true));
      x = tri.twin(T::prev(x));
      if (x == kInvalidIndex) return false;
    }
    if (x == o_u) return false;
  }
  return false;
}

PathStep reversed(PathStep s) { return {s.edge, !s.forward}; }

// Start paths that pass the vertices next to `path` on their other side: for each step, around
// the third corner of the face on either side of it; for each interior vertex, around each of
// its two wedges. At most one per vertex.
std::vector<EdgePath> other_sides(const T& tri, const EdgePath& path) {
  std::vector<EdgePath> out;
  std::vector<char> tried(static_cast<std::size_t>(tri.n_vertices()), 0);
  auto add = [&](std::size_t first, std::size_t count, Index c, const std::vector<PathStep>& r) {
    EdgePath p;
    p.steps.assign(path.steps.begin(), path.steps.begin() + first);
    p.steps.insert(p.steps.end(), r.begin(), r.end());
    p.steps.insert(p.steps.end(), path.steps.begin() + first + count, path.steps.end());
    out.push_back(std::move(p));
    tried[c] = 1;
  };
  const std::size_t n = path.steps.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Index h = step_halfedge(tri, path.steps[i]);
    for (const Index side : {h, h == kInvalidIndex ? kInvalidIndex : tri.twin(h)}) {
      if (side == kInvalidIndex) continue;
      const Index c = tri.tail(T::prev(side));
      if (tried[c]) continue;
      std::vector<PathStep> r;
      const bool left = side == h;  // the face on the path's left: its corner c, turn clockwise
      const Index o_u = left ? T::prev(side) : tri.twin(T::next(side));
      const Index o_w = left ? tri.twin(T::next(side)) : T::prev(side);
      if (o_u != kInvalidIndex && o_w != kInvalidIndex && around_vertex(tri, o_u, o_w, left, &r)) {
        add(i, 1, c, r);
      }
    }
  }
  for (std::size_t i = 1; i < n; ++i) {
    const Index c = step_tail(tri, path.steps[i]);
    if (tried[c]) continue;
    const Index o_u = step_halfedge(tri, reversed(path.steps[i - 1]));
    const Index o_w = step_halfedge(tri, path.steps[i]);
    if (o_u == kInvalidIndex || o_w == kInvalidIndex) continue;
    for (const bool cw : {true, false}) {
      std::vector<PathStep> r;
      if (around_vertex(tri, o_u, o_w, cw, &r)) add(i - 1, 2, c, r);
    }
  }
  return out;
}

}  // namespace

namespace {

// shorten_over_sides() that stops searching once the length is at most `enough`.
FlipOutReport shorten_over_sides_to(SignpostTriangulation& st, EdgePath& path,
                                    const FlipOutOptions& options, int rounds, double enough) {
  const bool opened = !st.recording_flips();
  FlipOutReport rep = shorten(st, path, options);
  const double initial = rep.initial_length;
  for (int r = 0; r < rounds && rep.final_length > enough; ++r) {
    bool better = false;
    for (const EdgePath& start : other_sides(st.intrinsic(), path)) {
      const std::size_t mark = st.flip_journal_mark();
      EdgePath p = start;
      const FlipOutReport t = shorten(st, p, options);
      if (t.final_length < rep.final_length * (1.0 - 1e-12)) {
        path = std::move(p), rep = t, better = true;
        break;
      }
      st.undo_flips(mark);  // the trial's flips only: st is the one the geodesic lies on again
    }
    if (!better) break;
  }
  if (opened && st.recording_flips()) st.end_flip_journal();
  rep.initial_length = initial;
  return rep;
}

}  // namespace

FlipOutReport shorten_over_sides(SignpostTriangulation& st, EdgePath& path,
                                 const FlipOutOptions& options, int rounds) {
  return shorten_over_sides_to(st, path, options, rounds, 0.0);
}

}  // namespace ifem::intrinsic

namespace ifem::intrinsic {

void ShortestGeodesicOptions::validate() const {
  flipout.validate();
  if (side_rounds < 0) {
    throw InvalidInput("ShortestGeodesicOptions::side_rounds must be ≥ 0, got " +
                       std::to_string(side_rounds));
  }
}

namespace {

bool same_steps(const EdgePath& p, const EdgePath& q) {
  return std::equal(p.steps.begin(), p.steps.end(), q.steps.begin(), q.steps.end(),
                    [](const PathStep& x, const PathStep& y) {
                      return x.edge == y.edge && x.forward == y.forward;
                    });
}

// True when starts[i] repeats an earlier start (its FlipOut and side search would too).
bool repeats_earlier(const std::vector<EdgePath>& starts, std::size_t i) {
  for (std::size_t j = 0; j < i; ++j) {
    if (same_steps(starts[j], starts[i])) return true;
  }
  return false;
}

EdgePath reversed_path(const EdgePath& p) {
  EdgePath r;
  for (auto it = p.steps.rbegin(); it != p.steps.rend(); ++it) r.steps.push_back(reversed(*it));
  return r;
}

// Start i of a search, made when it is needed (after the flips of start i − 1 are undone):
// false when there is none left.
using StartSource = std::function<bool(std::size_t i, EdgePath* start, std::string* name)>;

// Shortens every distinct start on st itself (its flips undone after it) and redoes the
// shortest result's flips at the end (shortest_geodesic()); stops at a start reaching `enough`.
FlipOutReport shorten_starts(SignpostTriangulation& st, const StartSource& next,
                             const ShortestGeodesicOptions& o, EdgePath* path, std::string* won,
                             double enough = 0.0) {
  const bool opened = !st.recording_flips();
  const std::size_t mark = st.flip_journal_mark();
  std::vector<EdgePath> starts;
  std::vector<Index> best_flips;
  FlipOutReport best_report;
  std::string name;
  for (std::size_t i = 0;; ++i) {
    EdgePath start;
    if (!next(i, &start, &name)) break;
    starts.push_back(std::move(start));
    if (repeats_earlier(starts, i)) continue;
    EdgePath p = starts[i];
    const FlipOutReport r = shorten_over_sides_to(st, p, o.flipout, o.side_rounds, enough);
    if (i == 0 || r.final_length < best_report.final_length) {
      best_report = r, *path = std::move(p), best_flips = st.flips_since(mark);
      if (won != nullptr) *won = name;
    }
    st.undo_flips(mark);
    if (best_report.final_length <= enough) break;
  }
  if (opened) st.end_flip_journal();
  for (const Index e : best_flips) st.flip_edge(e);
  return best_report;
}

FlipOutReport shorten_starts(SignpostTriangulation& st, const std::vector<EdgePath>& starts,
                             const std::vector<std::string>& names,
                             const ShortestGeodesicOptions& o, EdgePath* path, std::string* won) {
  const StartSource next = [&](std::size_t i, EdgePath* start, std::string* name) {
    if (i >= starts.size()) return false;
    *start = starts[i], *name = names[i];
    return true;
  };
  return shorten_starts(st, next, o, path, won);
}

}  // namespace

FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                const Eigen::VectorXd* guide_to_b,
                                const Eigen::VectorXd* guide_to_a, const ShortestGeodesicOptions& o,
                                EdgePath* path, std::string* won) {
  o.validate();
  const T& tri = st.intrinsic();
  std::vector<EdgePath> starts{shortest_edge_path(tri, a, b)};  // validates a and b
  std::vector<std::string> names{"shortest edge path"};
  if (o.start == StartPath::kDijkstra || (guide_to_b == nullptr && guide_to_a == nullptr)) {
    *path = starts[0];
    if (won != nullptr) *won = names[0];
    return shorten(st, *path, o.flipout);
  }
  if (o.start == StartPath::kGuided) starts.clear(), names.clear();
  const char* side_names[3] = {"shorter", "left", "right"};
  for (int k = 0; k < 3; ++k) {
    const auto side = static_cast<StripSide>(k);
    if (guide_to_b) {
      starts.push_back(descent_edge_path(tri, a, b, *guide_to_b, side));
      names.push_back(std::string("descent to b, ") + side_names[k] + " side");
    }
    if (guide_to_a) {
      starts.push_back(reversed_path(descent_edge_path(tri, b, a, *guide_to_a, side)));
      names.push_back(std::string("descent to a, reversed, ") + side_names[k] + " side");
    }
  }
  return shorten_starts(st, starts, names, o, path, won);
}

FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                const ExactDistance& exact_to_b, const ExactDistance* exact_to_a,
                                const ShortestGeodesicOptions& o, EdgePath* path,
                                std::string* won) {
  return shortest_geodesic(
      st, a, b, exact_to_b, [exact_to_a] { return exact_to_a; }, o, path, won);
}

FlipOutReport shortest_geodesic(SignpostTriangulation& st, Index a, Index b,
                                const ExactDistance& exact_to_b,
                                const std::function<const ExactDistance*()>& exact_to_a,
                                const ShortestGeodesicOptions& o, EdgePath* path,
                                std::string* won) {
  o.validate();
  const T& tri = st.intrinsic();
  EdgePath dijkstra = shortest_edge_path(tri, a, b);  // validates a and b
  if (o.start == StartPath::kDijkstra) {
    *path = std::move(dijkstra);
    if (won != nullptr) *won = "shortest edge path";
    return shorten(st, *path, o.flipout);
  }
  // the starts in their order: (kind, side); kind 0/1 the exact geodesic's strips to b / to a
  // (reversed), 2 the Dijkstra path (kBest), 3/4 the descents to b / to a (reversed)
  std::vector<std::pair<int, int>> order;
  for (int k = 0; k < 3; ++k) order.push_back({0, k}), order.push_back({1, k});
  if (o.start == StartPath::kBest) order.push_back({2, 0});
  for (int k = 0; k < 3; ++k) order.push_back({3, k}), order.push_back({4, k});
  // the exact distance to a only when a start needs it (after the first one fell short)
  bool asked = false;
  const ExactDistance* to_a = nullptr;
  const char* side_names[3] = {"shorter", "left", "right"};
  std::size_t cursor = 0;
  const StartSource next = [&](std::size_t, EdgePath* start, std::string* name) {
    for (; cursor < order.size(); ++cursor) {
      const auto [kind, k] = order[cursor];
      const auto side = static_cast<StripSide>(k);
      if ((kind == 1 || kind == 4) && !asked) asked = true, to_a = exact_to_a();
      if ((kind == 1 || kind == 4) && to_a == nullptr) continue;
      const std::string s = side_names[k];
      if (kind == 0) *start = exact_edge_path(tri, a, b, exact_to_b, side);
      if (kind == 0) *name = "exact geodesic to b, " + s + " side";
      if (kind == 1) *start = reversed_path(exact_edge_path(tri, b, a, *to_a, side));
      if (kind == 1) *name = "exact geodesic to a, reversed, " + s + " side";
      if (kind == 2) *start = dijkstra, *name = "shortest edge path";
      if (kind == 3) *start = descent_edge_path(tri, a, b, exact_to_b.distance, side);
      if (kind == 3) *name = "descent to b, " + s + " side";
      if (kind == 4) *start = reversed_path(descent_edge_path(tri, b, a, to_a->distance, side));
      if (kind == 4) *name = "descent to a, reversed, " + s + " side";
      ++cursor;
      return true;
    }
    return false;
  };
  // the exact distance is the length to reach: later starts only where FlipOut falls short
  const double enough = exact_to_b.distance[a] * (1.0 + 1e-12);
  return shorten_starts(st, next, o, path, won, enough);
}

}  // namespace ifem::intrinsic
